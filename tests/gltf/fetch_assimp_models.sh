#!/bin/sh
# Test set-up: fetch Debian's assimp-testmodels package and unpack its glTF2 folder into
# $1/glTF2 (real sample assets and deliberately broken files). Offline, it leaves nothing
# behind and exits 0: the tests that need the files skip themselves.
set -u
dest=${1:?usage: fetch_assimp_models.sh DEST}
[ -d "$dest/glTF2" ] && exit 0
mkdir -p "$dest"
work=$(mktemp -d "$dest/fetch.XXXXXX") || exit 0
trap 'rm -rf "$work"' EXIT
deb=$(ls /var/cache/apt/archives/assimp-testmodels_*.deb 2>/dev/null | head -n 1)
if [ -z "$deb" ]; then
  if ! (cd "$work" && timeout 300 apt-get download assimp-testmodels >/dev/null 2>&1); then
    echo "fetch_assimp_models: cannot download assimp-testmodels (offline?); real-file tests will be skipped"
    exit 0
  fi
  deb=$(ls "$work"/assimp-testmodels_*.deb | head -n 1)
fi
if ! dpkg -x "$deb" "$work/root"; then
  echo "fetch_assimp_models: cannot unpack $deb; real-file tests will be skipped"
  exit 0
fi
mv "$work/root/usr/share/assimp/models/glTF2" "$dest/glTF2.partial" && mv "$dest/glTF2.partial" "$dest/glTF2"
echo "fetch_assimp_models: unpacked $(find "$dest/glTF2" -type f | wc -l) files into $dest/glTF2"
