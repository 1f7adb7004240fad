#!/usr/bin/env bash
# Scaling past two cores (docs/performance.md): runs the reconstruction and the frame loop of one
# or more benchmark bundles (tools/bench_bundle.sh) on this machine, on 1, 2, 4, ... cores, and
# writes Google Benchmark JSON for bench/scaling_tables.py. Builds given together are measured in
# the same run, one after the other, so their ratios are comparable.
#   bench/scaling_run.sh OUT_DIR LABEL=BUNDLE.tar.xz [LABEL=BUNDLE.tar.xz ...]
# Environment (defaults in brackets):
#   SCALING_RECONSTRUCT   epi_bench filter [1080p and 4K, tiled stream, best target, all threads]
#   SCALING_FRAME         render_bench filter, run once per scene with SCENE replaced by its index
#                         [BM_FrameThreads: 1080p, the loop held to 1, 2, 4, ... threads up to the
#                         cores by a task arena]
#   SCALING_TABLE2        render_bench filter run on 2 cores, the paper's table 2 [every scene, 512²]
#   SCALING_STAGES        render_stages_bench filter [the sparse blend at 1080p, oracle and kernels,
#                         1, 2, 4, ... threads]
#   SCALING_POINTS        render_points_bench filter, fast path only [every scene's point stages at
#                         1080p, epi mode, 1, 2, 4, ... threads]
# Any of them "none" skips that part.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OUT_DIR LABEL=BUNDLE.tar.xz [...]" >&2; exit 2; }
out=$1; shift
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
mkdir -p "$out"
reconstruct=${SCALING_RECONSTRUCT:-'BM_StreamingFloor/(1920|3840)|BM_Reconstruct/(1920/1080|3840/2160)/1/'}
frame=${SCALING_FRAME:-'BM_FrameThreads/SCENE/1920/1080/'}
table2=${SCALING_TABLE2:-'BM_Frame/[0-4]/512/512/2/'}
stages=${SCALING_STAGES:-'BM_SparseBlend/1920/1080/10/'}
points=${SCALING_POINTS:-'BM_Points/[0-4]/1920/1080/0/'}
json=(--benchmark_out_format=json)
for spec in "$@"; do
  label=${spec%%=*} bundle=${spec#*=}
  [ -f "$bundle" ] || { echo "$0: $bundle: no such bundle" >&2; exit 1; }
  dir=$(mktemp -d)
  tar xJf "$bundle" -C "$dir"
  b=$dir/b
  src=$(cat "$b/source_dir")
  if [ ! -e "$src/scenes" ]; then
    mkdir -p "$(dirname "$src")" && ln -sfn "$root" "$src" || { echo "$0: cannot link $src to $root (the scenes)" >&2; exit 1; }
  fi
  export LD_LIBRARY_PATH=$b/lib
  if [ "$stages" != none ]; then
    echo "== $label: frame-loop stages on 1, 2, 4, ... threads"
    "$b/render_stages_bench" --benchmark_filter="$stages" --benchmark_out="$out/${label}_stages.json" "${json[@]}" 2>&1 | grep -E "^BM_" | cut -c1-160
  fi
  if [ "$points" != none ]; then
    echo "== $label: point stages on 1, 2, 4, ... threads ($(date +%T))"
    EPI_POINTS_FAST_ONLY=1 "$b/render_points_bench" --benchmark_filter="$points" --benchmark_out="$out/${label}_points.json" "${json[@]}" 2>&1 | grep -E "^BM_" | cut -c1-160
  fi
  if [ "$frame" != none ]; then
    # One run per scene (LABEL_frame_sK.json), so that a run cut off at a time limit keeps the
    # scenes that finished.
    for k in 0 1 2 3 4; do
      echo "== $label: frame loop on 1, 2, 4, ... threads, scene $k ($(date +%T))"
      "$b/render_bench" --benchmark_filter="${frame//SCENE/$k}" --benchmark_out="$out/${label}_frame_s$k.json" "${json[@]}" 2>&1 | grep -E "^BM_" | cut -c1-160
    done
  fi
  echo "== $label: reconstruction"
  [ "$reconstruct" = none ] || "$b/epi_bench" --benchmark_filter="$reconstruct" --benchmark_out="$out/${label}_reconstruct.json" "${json[@]}" 2>&1 | grep -E "^BM_"
  if [ "$table2" != none ]; then
    echo "== $label: table 2 on 2 cores"
    taskset -c 0-1 "$b/render_bench" --benchmark_filter="$table2" --benchmark_out="$out/${label}_table2.json" "${json[@]}" 2>&1 | grep -E "^BM_" | cut -c1-160
  fi
  rm -rf "$dir"
done
