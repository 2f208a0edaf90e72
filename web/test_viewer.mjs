// The web viewer in a real browser (Debian's chromium driven by playwright-core): a tileset made
// by `gausslod --3dtiles` is loaded, the level on screen changes between a near and a far camera as
// the tiles' errors say it should (near: a finer level than far; far: the root, the coarsest),
// pixels are drawn, the console has no error. Also a `--lod-file` chain through MSFT_lod.
//   node web/test_viewer.mjs TILES_DIR [--shots DIR] [--glb NAME_lods.glb]
// Exit 0 if every check held. --shots saves the near and far screenshots.
import { spawn } from 'node:child_process';
import { mkdirSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = path.dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const dir = args[0];
const opt = (name) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : null; };
const shots = opt('--shots');
const glb = opt('--glb');
let failures = 0;
const check = (ok, what) => { console.log(`${ok ? 'ok' : 'FAIL'}: ${what}`); if (!ok) failures++; };

// the viewer's server on a free port
const server = spawn('python3', [path.join(here, 'serve.py'), dir, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  server.stdout.on('data', (d) => { const m = /http:\/\/[^/]+\//.exec(String(d)); if (m) resolve(m[0]); });
  server.on('exit', (c) => reject(new Error('serve.py exited ' + c)));
  setTimeout(() => reject(new Error('serve.py did not start')), 15000);
});

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--ignore-gpu-blocklist', '--no-sandbox'],
});
const consoleErrors = [];

async function view(query, name) {
  const page = await browser.newPage({ viewport: { width: 800, height: 600 } });
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(`${name}: ${m.text()}`); });
  page.on('pageerror', (e) => consoleErrors.push(`${name}: ${e.message}`));
  await page.goto(url + query);
  try {
    await page.waitForFunction(() => window.viewerState && (window.viewerState.ready || window.viewerState.error),
                               null, { timeout: 60000 });
  } catch (e) {
    consoleErrors.push(`${name}: not ready in 60 s`);
  }
  const state = await page.evaluate(() => window.viewerState);
  const drawn = await page.evaluate(() => window.drawnPixels());
  if (shots) {
    mkdirSync(shots, { recursive: true });
    await page.screenshot({ path: path.join(shots, `viewer_${name}.png`) });
  }
  await page.close();
  return { state, drawn };
}

try {
  const near = await view('?tileset=tiles/tileset.json&distance=1.3', 'near');
  const mid = await view('?tileset=tiles/tileset.json&distance=8', 'mid');
  const far = await view('?tileset=tiles/tileset.json&distance=60', 'far');
  const lodOf = (v) => Math.min(...v.state.shown.map((t) => t.lod));
  console.log('near:', JSON.stringify(near.state.shown), near.drawn, 'pixels');
  console.log('far:', JSON.stringify(far.state.shown), far.drawn, 'pixels');
  console.log('mid:', JSON.stringify(mid.state.shown), mid.drawn, 'pixels');
  check(near.state.ready && far.state.ready && !near.state.error && !far.state.error, 'the tileset loads near and far');
  check(near.state.shown.length > 0 && far.state.shown.length > 0, 'a level is on screen near and far');
  check(lodOf(near) < lodOf(far), `near shows a finer level (LOD${lodOf(near)}) than far (LOD${lodOf(far)})`);
  check(lodOf(near) <= lodOf(mid) && lodOf(mid) <= lodOf(far), `farther, never finer (LOD${lodOf(near)}, ${lodOf(mid)}, ${lodOf(far)})`);
  const maxLod = Math.max(...far.state.shown.map((t) => t.lod));
  check(far.state.shown.every((t) => t.level === 0) && maxLod > 0, 'far shows the root (the coarsest level, paper level 0)');
  // the errors say it: each level shown has its screen-space error (its geometricError seen from
  // the camera) within the target, or is the input, and the coarser one above it has not
  for (const [v, name] of [[near, 'near'], [mid, 'mid'], [far, 'far']])
    check(v.state.shown.every((t) => (t.leaf || t.sse <= v.state.errorTarget) &&
                                    (t.parentSse === null || t.parentSse > v.state.errorTarget)),
          `${name}: the level shown is the coarsest whose error is within ${v.state.errorTarget} px ` +
          JSON.stringify(v.state.shown.map((t) => [t.lod, t.sse, t.parentSse])));
  check(near.drawn > 2000 && far.drawn > 20, `pixels drawn (near ${near.drawn}, far ${far.drawn})`);
  if (glb) {
    const chain = await view(`?glb=tiles/${glb}&distance=1.3`, 'glb_near');
    const chainFar = await view(`?glb=tiles/${glb}&distance=200`, 'glb_far');
    console.log('MSFT_lod near/far:', JSON.stringify(chain.state.shown), JSON.stringify(chainFar.state.shown));
    check(chain.state.ready && chainFar.state.ready, 'the MSFT_lod chain loads');
    check(chain.state.shown[0].lod < chainFar.state.shown[0].lod, 'MSFT_lod: near finer than far');
    check(chain.drawn > 2000, `MSFT_lod: pixels drawn (${chain.drawn})`);
  }
  check(consoleErrors.length === 0, 'no console error' + (consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''));
} finally {
  await browser.close();
  server.kill();
}
console.log(`web.viewer: ${failures} failure(s)`);
process.exit(failures ? 1 : 0);
