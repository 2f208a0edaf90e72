#!/usr/bin/env python3
"""Serves GaussLOD's web viewer (this folder, with its npm packages) and a folder of levels:
    python3 web/serve.py DIR [--port 8080] [--bind 127.0.0.1]
DIR (a `gausslod --3dtiles` or `--lod-file` output folder) is served under /tiles/; open
http://127.0.0.1:8080/?tileset=tiles/tileset.json (or ?glb=tiles/NAME_lods.glb)."""
import argparse, functools, http.server, os, posixpath, sys, urllib.parse

HERE = os.path.dirname(os.path.abspath(__file__))


class Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".js": "text/javascript", ".mjs": "text/javascript",
                      ".glb": "model/gltf-binary", ".json": "application/json"}
    tiles = None

    def translate_path(self, path):
        path = urllib.parse.unquote(urllib.parse.urlsplit(path).path)
        parts = [p for p in posixpath.normpath(path).split("/") if p not in ("", ".", "..")]
        if parts and parts[0] == "tiles":
            return os.path.join(self.tiles, *parts[1:])
        return os.path.join(HERE, *parts)

    def log_message(self, *args):
        pass


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--port", type=int, default=8080)
    ap.add_argument("--bind", default="127.0.0.1")
    a = ap.parse_args()
    if not os.path.isdir(os.path.join(HERE, "node_modules", "three")):
        sys.exit("serve.py: web/node_modules is missing: run bash cmake/setup.sh (or npm install "
                 "--no-package-lock in web/)")
    Handler.tiles = os.path.abspath(a.dir)
    server = http.server.ThreadingHTTPServer((a.bind, a.port), Handler)
    print("GaussLOD viewer: http://%s:%d/?tileset=tiles/tileset.json" % (a.bind, server.server_address[1]),
          flush=True)
    server.serve_forever()


if __name__ == "__main__":
    main()
