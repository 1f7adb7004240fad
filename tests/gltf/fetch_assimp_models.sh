#!/bin/sh
# Test set-up: fetch Debian's assimp-testmodels package and unpack its glTF2 folder into
# $1/glTF2 (real sample assets and deliberately broken files).
# If it cannot (offline, no package lists): outside CI it says so, leaves nothing behind and
# exits 0, and the tests that need the files skip themselves with that message; in CI (the
# environment variable CI is set, as .ci/run has it) it exits 1, so the set-up test fails and
# the real-file tests do not pass silently.
set -u
dest=${1:?usage: fetch_assimp_models.sh DEST}
[ -d "$dest/glTF2" ] && exit 0

give_up() {
  if [ -n "${CI:-}" ]; then
    echo "fetch_assimp_models: $1; CI is set, so this fails (the real-file tests must run in CI)" >&2
    exit 1
  fi
  echo "fetch_assimp_models: $1; the real-file tests will be skipped"
  exit 0
}

mkdir -p "$dest" || give_up "cannot create $dest"
work=$(mktemp -d "$dest/fetch.XXXXXX") || give_up "cannot create a folder in $dest"
trap 'rm -rf "$work"' EXIT
deb=$(ls /var/cache/apt/archives/assimp-testmodels_*.deb 2>/dev/null | head -n 1)
if [ -z "$deb" ]; then
  if ! (cd "$work" && timeout 300 apt-get download assimp-testmodels >/dev/null 2>&1); then
    give_up "cannot download assimp-testmodels with apt-get download (offline, or no package lists: apt-get update)"
  fi
  deb=$(ls "$work"/assimp-testmodels_*.deb | head -n 1)
fi
dpkg -x "$deb" "$work/root" || give_up "cannot unpack $deb"
[ -d "$work/root/usr/share/assimp/models/glTF2" ] || give_up "$deb has no usr/share/assimp/models/glTF2"
mv "$work/root/usr/share/assimp/models/glTF2" "$dest/glTF2.partial" && mv "$dest/glTF2.partial" "$dest/glTF2" ||
  give_up "cannot move the files into $dest/glTF2"
echo "fetch_assimp_models: unpacked $(find "$dest/glTF2" -type f | wc -l) files into $dest/glTF2"
