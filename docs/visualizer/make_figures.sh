#!/usr/bin/env bash
# Regenerates the figures of docs/visualizer.md from the built epi-visualizer (and epi for the
# snapshot): each figure is one exported step, picked by stage and position within the stage.
#   docs/visualizer/make_figures.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${1:-$root/build}/bin
out=$root/docs/visualizer
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# pick NAME EXPORT_DIR STAGE K: copy the K-th step (0-based; negative from the end) of STAGE.
pick() {
  local file
  file=$(/usr/bin/python3 -c "import json,sys; j=json.load(open('$2/trace.json')); s=[t for t in j['steps'] if t['stage']==$3]; print(s[$4]['png'])")
  cp "$2/$file" "$out/$1.png"
}

"$bin/epi-visualizer" checkerboard --export "$work/checker" >/dev/null
pick classification "$work/checker" 3 0
pick reachability-diagonal "$work/checker" 4 10
pick reachability-mask "$work/checker" 4 -1
pick antialiasing "$work/checker" 6 -1
"$bin/epi-visualizer" wedges --density 0.06 --pixel 9,12 --export "$work/wedges" >/dev/null
pick pixel-side "$work/wedges" 2 -3
pick fallback "$work/wedges" 5 2
"$bin/epi-visualizer" slivers --export "$work/slivers" >/dev/null
pick complex-regions "$work/slivers" 7 2
pick complex-result "$work/slivers" 7 -1
"$bin/epi" render "$root/scenes/cornell_box.gltf" --mode epi --size 160x120 --frames 8 --sample-budget 0.05 --sync --quiet \
  -o "$work/frame.png" --save-epi "$work/frame.epis"
"$bin/epi-visualizer" "$work/frame.epis" --pixel 80,60 --export "$work/snapshot" >/dev/null
pick snapshot-input "$work/snapshot" 1 0
pick snapshot-reachability "$work/snapshot" 4 -1
if command -v xvfb-run >/dev/null; then
  xvfb-run -a -s "-screen 0 1600x900x24" "$bin/epi-visualizer" checkerboard --step 30 --screenshot "$out/window.png"
fi
echo "figures written to $out"
