#!/usr/bin/env bash
# Install what the viewer's browser tests need on a Debian machine: Debian's chromium and a
# font (apt), and three.js from the npm registry at the version pinned by the committed
# package-lock.json (npm ci). Idempotent: does nothing slow when everything is in place.
#
#   bash scripts/install_browser_deps.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
web="$root/src/posekit/viewer/web"

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo "$@"; else
        echo "install_browser_deps: need root (or sudo) for: $*" >&2; return 1; fi
}

need_apt=()
[ -x /usr/bin/chromium ] || need_apt+=(chromium)
[ -e /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ] || need_apt+=(fonts-dejavu-core)
command -v npm >/dev/null 2>&1 || need_apt+=(npm)
command -v dot >/dev/null 2>&1 || need_apt+=(graphviz)  # view_frames writes its PDF with dot
if [ "${#need_apt[@]}" -gt 0 ]; then
    echo "install_browser_deps: apt-get install ${need_apt[*]}"
    as_root apt-get update -q
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${need_apt[@]}"
fi

# npm ci only when node_modules does not hold exactly the versions of the lockfile.
in_sync() {
    (cd "$web" && node -e '
        const lock = require("./package-lock.json").packages;
        for (const [path, entry] of Object.entries(lock)) {
            if (!path) continue;
            let have;
            try { have = require("./" + path + "/package.json").version; } catch { process.exit(1); }
            if (have !== entry.version) process.exit(1);
        }' ) 2>/dev/null
}
if ! in_sync; then
    echo "install_browser_deps: npm ci in $web"
    (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
fi
echo "install_browser_deps: chromium $(/usr/bin/chromium --version 2>/dev/null | awk '{print $2}'), three $(node -p "require('$web/node_modules/three/package.json').version" 2>/dev/null || echo '?')"
