#!/usr/bin/env bash
# Install what the viewer's browser tests need on a Debian machine: Debian's chromium, a font
# and graphviz (apt). three.js is vendored in the package (src/posekit/viewer/web/vendor/three),
# so nothing comes from npm. Idempotent: does nothing slow when everything is in place.
#
#   bash scripts/install_browser_deps.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
three="$root/src/posekit/viewer/web/vendor/three"

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo "$@"; else
        echo "install_browser_deps: need root (or sudo) for: $*" >&2; return 1; fi
}

need_apt=()
[ -x /usr/bin/chromium ] || need_apt+=(chromium)
[ -e /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ] || need_apt+=(fonts-dejavu-core)
command -v dot >/dev/null 2>&1 || need_apt+=(graphviz)  # view_frames writes its PDF with dot
if [ "${#need_apt[@]}" -gt 0 ]; then
    echo "install_browser_deps: apt-get install ${need_apt[*]}"
    as_root apt-get update -q
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${need_apt[@]}"
fi

echo "install_browser_deps: chromium $(/usr/bin/chromium --version 2>/dev/null | awk '{print $2}'), $(head -n1 "$three/VERSION" 2>/dev/null || echo 'three.js: vendored copy missing') (vendored)"
