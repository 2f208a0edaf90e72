"""Summary of bench/certified_check.sh's lines (files given; '== MODE' lines separate chains):
the certified / sampled ratio over levels whose sampled distance is at least 1e-4 % of the
diagonal (below, float rounding of the level files decides), the construction's bound over the
sampled distance, and the certification's and the levels' total seconds per chain."""
import statistics,sys
rows=[]
mode=None
for line in (l for p in sys.argv[1:] for l in open(p)):
    if line.startswith('=='): mode=line.split()[1]; continue
    f=line.split()
    if len(f)<10: continue
    rows.append(dict(mode=mode,model=f[0],lvl=f[1],faces=int(f[2]),cert=float(f[4]),samp=float(f[6]),ratio=float(f[8]),bs=float(f[10]),tc=float(f[14]),tl=float(f[16])))
big=[r for r in rows if r['samp']>=1e-4]
small=[r for r in rows if r['samp']<1e-4]
rs=[r['ratio'] for r in big]
print(len(rows),'levels;',len(big),'with sampled >= 1e-4 %%: ratio median %.3f max %.3f min %.3f'%(statistics.median(rs),max(rs),min(rs)))
print('bound/sampled median %.2f'%statistics.median([r['bs'] for r in big]))
print('small:',[(r['model'],r['lvl'],r['cert'],r['samp']) for r in small])
for m in sorted(set(r['mode'] for r in rows)):
    sub=[r for r in rows if r['mode']==m]
    print(m, 'tcert %.2f tlevel %.2f'%(sum(r['tc'] for r in sub), sum(r['tl'] for r in sub)))
