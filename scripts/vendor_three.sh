#!/usr/bin/env bash
# Re-vendor three.js into the viewer package (src/posekit/viewer/web/vendor/three): the npm
# tarball of the pinned version, checked against its pinned sha512, and only the files the
# page imports (the core module, its build dependency, OrbitControls) plus the licence.
# The vendored copy is committed; nothing runs this at install or run time.
#
#   bash scripts/vendor_three.sh            # needs npm (or curl) and network, once
set -euo pipefail

VERSION=0.187.0
INTEGRITY="sha512-Qiu7R+Cmh8CstZsY1uJOSWnVlfo7ZtNLV7mF8Jltk3LB3AtDu9cRZlcnRKkAk8Y4z6KKw35z7Y7Urd7jWY8etA=="
FILES=(build/three.module.js build/three.core.js examples/jsm/controls/OrbitControls.js LICENSE)

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dest="$root/src/posekit/viewer/web/vendor/three"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

(cd "$work" && npm pack "three@$VERSION" --silent >/dev/null)
have="sha512-$(openssl dgst -sha512 -binary "$work/three-$VERSION.tgz" | base64 -w0)"
if [ "$have" != "$INTEGRITY" ]; then
    echo "vendor_three: three-$VERSION.tgz has $have, expected $INTEGRITY" >&2
    exit 1
fi
tar -xzf "$work/three-$VERSION.tgz" -C "$work"
rm -rf "$dest"
for f in "${FILES[@]}"; do
    install -D -m 0644 "$work/package/$f" "$dest/$f"
done
printf 'three %s\nnpm tarball integrity %s\nfiles: %s\n' "$VERSION" "$INTEGRITY" "${FILES[*]}" \
    > "$dest/VERSION"
echo "vendor_three: three $VERSION in $dest"
