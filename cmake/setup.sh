#!/usr/bin/env bash
# Installs what GaussLOD needs on a Debian bookworm machine, idempotently, as root.
#  1. Debian packages (apt-get update only when something is missing);
#  2. the Debian SOURCE package of the installed meshlab (MeshLab src/common + vcglib headers),
#     unpacked once into $GAUSSLOD_DEPS (default: <repo>/.deps, git-ignored);
#  3. Debian's libcgal-demo data (real test models), unpacked into the same folder.
# Real files users have (STL soups, textured OBJ with materials, broken files from importer
# regression suites) come from the package assimp-testmodels (/usr/share/assimp/models).
# A deb-src entry is derived from the machine's own apt configuration; no host name is written here.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
deps=${GAUSSLOD_DEPS:-$here/.deps}
mkdir -p "$deps"

need_root() {
  if [ "$(id -u)" != 0 ]; then
    if command -v sudo >/dev/null; then sudo "$@"; else echo "setup: need root for: $*" >&2; exit 1; fi
  else "$@"; fi
}

pkgs=(meshlab qtbase5-dev libqt5opengl5-dev libqt5xmlpatterns5-dev libglew-dev libglu1-mesa-dev
      libeigen3-dev cmake g++ make xvfb xauth libgtest-dev libcgal-dev libgmp-dev libmpfr-dev
      dpkg-dev xdotool imagemagick x11-utils clang libclang-rt-14-dev
      assimp-testmodels parallel valgrind libtinygltf-dev chromium clang-format)
# Node.js and npm (the web viewer's packages and its browser test): Debian's only where the machine
# has none of its own (Debian's npm conflicts with a Node.js installed otherwise)
command -v node >/dev/null && command -v npm >/dev/null || pkgs+=(nodejs npm)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
updated=0
apt_update() { [ $updated = 1 ] || { need_root apt-get update -qq; updated=1; }; }
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  apt_update
  need_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# --- MeshLab + VCGLib headers from the Debian source package of the installed version -------------
ver=$(dpkg-query -W -f='${Version}' meshlab)
src="$deps/meshlab-src-$ver"
if [ ! -f "$src/.unpacked" ]; then
  # deb-src entries mirroring the configured deb entries (deb822 and one-line formats).
  srcfile=/etc/apt/sources.list.d/gausslod-deb-src.sources
  if ! grep -rqs '^Types:.*deb-src\|^deb-src ' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    tmp=$(mktemp)
    for f in /etc/apt/sources.list.d/*.sources; do
      [ -f "$f" ] || continue
      # every deb822 stanza whose Types include deb becomes a deb-src stanza (same URIs/Suites/...)
      awk '
        function flush() { if (isdeb && buf != "") printf "%s\n", buf; buf=""; isdeb=0 }
        /^[ \t]*$/ { flush(); next }
        /^#/ { next }
        /^Types:/ { n=split($0, t, /[ \t]+/); for (k=2;k<=n;k++) if (t[k]=="deb") isdeb=1
                    buf=buf "Types: deb-src\n"; next }
        { buf=buf $0 "\n" }
        END { flush() }' "$f" >>"$tmp"
    done
    if [ -f /etc/apt/sources.list ]; then
      grep -E '^deb ' /etc/apt/sources.list | sed 's/^deb /deb-src /' >"$tmp.list" || true
      [ -s "$tmp.list" ] && need_root cp "$tmp.list" /etc/apt/sources.list.d/gausslod-deb-src.list
    fi
    [ -s "$tmp" ] && need_root cp "$tmp" "$srcfile"
    rm -f "$tmp" "$tmp.list"
    updated=0
  fi
  apt_update
  dl="$deps/meshlab-download"
  rm -rf "$dl" "$src"; mkdir -p "$dl"
  (cd "$dl" && apt-get source --download-only "meshlab=$ver" >/dev/null)
  dpkg-source -x "$dl"/meshlab_*.dsc "$src" >/dev/null
  rm -rf "$dl"
  touch "$src/.unpacked"
fi
ln -sfn "$src" "$deps/meshlab-src"

# --- Real models from Debian's libcgal-demo (no install needed: unpack the .deb's data) ----------
if [ ! -f "$deps/cgal-data/.unpacked" ]; then
  tarball=/usr/share/doc/libcgal-dev/data.tar.gz
  if [ ! -f "$tarball" ]; then
    dl=$(mktemp -d)
    apt_update
    (cd "$dl" && apt-get download libcgal-demo >/dev/null)
    dpkg -x "$dl"/libcgal-demo_*.deb "$dl/x"
    tarball="$dl/x/usr/share/doc/libcgal-dev/data.tar.gz"
  fi
  rm -rf "$deps/cgal-data"; mkdir -p "$deps/cgal-data"
  tar -xzf "$tarball" -C "$deps/cgal-data"
  touch "$deps/cgal-data/.unpacked"
fi
# --- npm packages of the web viewer and its tests (web/package.json: pinned versions, installed
# into web/node_modules without a lock file; nothing of them is committed) ------------------------
stamp="$here/web/node_modules/.gausslod-installed"
if [ ! -f "$stamp" ] || [ "$here/web/package.json" -nt "$stamp" ]; then
  echo "setup: npm install (web/package.json)"
  (cd "$here/web" && npm install --no-package-lock --no-audit --no-fund --loglevel=error >/dev/null)
  touch "$stamp"
fi
echo "setup: ok (deps in $deps)"
