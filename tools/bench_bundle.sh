#!/usr/bin/env bash
# Packs the frame-loop and reconstruction benchmarks of a Release build, with the shared libraries
# they load (all but the C library itself), into one tarball that runs on another x86-64 Linux
# machine without epi's Debian packages: how docs/performance.md measures scaling past two cores.
#   tools/bench_bundle.sh BUILD_DIR OUT.tar.xz
# The benchmarks read scenes from the source tree they were built from (EPI_SOURCE_DIR, compiled
# in); bench/scaling_run.sh links that path to the tree it runs in.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 BUILD_DIR OUT.tar.xz" >&2; exit 2; }
build=$1 out=$2
programs=(epi_bench render_bench render_points_bench render_stages_bench)
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/b/lib"
for p in "${programs[@]}"; do
  [ -x "$build/bin/$p" ] || { echo "$0: $build/bin/$p: not built (cmake --build $build --target $p)" >&2; exit 1; }
  cp "$build/bin/$p" "$stage/b/"
  ldd "$build/bin/$p" | awk '$3 ~ /^\// {print $3}'
done | sort -u | grep -vE '/(libc|libm)\.so|ld-linux' | while read -r lib; do cp -L "$lib" "$stage/b/lib/"; done
sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" > "$stage/b/source_dir"
tar cJf "$out" -C "$stage" b
echo "$out: $(du -h "$out" | cut -f1), source dir $(cat "$stage/b/source_dir")"
