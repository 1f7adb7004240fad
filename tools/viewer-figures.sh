#!/usr/bin/env bash
# The figures of docs/viewer.md, made by the viewer itself under a virtual X server:
#   1. one screenshot per stage view and one of the whole window (docs/images/viewer/),
#   2. the --benchmark figures at 512x512 and 1920x1080 (render scales 1, 0.75 and 0.5), written into docs/viewer.md between the
#      "viewer-benchmark" markers (with the machine and its load).
# Usage: tools/viewer-figures.sh [--benchmark-only] [BUILD_DIR]   (default: build; needs xvfb-run)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
benchmark_only=false
if [ "${1:-}" = --benchmark-only ]; then benchmark_only=true; shift; fi
build=${1:-$root/build}
viewer=$build/bin/epi-viewer
scene=$root/scenes/cornell_box.gltf
images=$root/docs/images/viewer
mkdir -p "$images"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if ! $benchmark_only; then
# 1. Stage views: the default Cornell box view, 320x320, after the cache has filled; the hovered
#    pixel (reachability view) sits on the short block's top edge.
{
  echo "wait 90"
  echo "move 200 212"
  names=(final points edges classes reachability priority depth)
  for k in 1 2 3 4 5 6 7; do
    echo "key F$k"
    echo "wait 2"
    echo "screenshot $images/stage-${names[$((k - 1))]}.png"
  done
} > "$work/stages.txt"
xvfb-run -a -s "-screen 0 1280x1024x24" "$viewer" "$scene" --size 320x320 --script "$work/stages.txt"
# Hard shadow edges (blue) need punctual lights: the edges view of rooms.gltf, and its final image.
printf 'wait 60\nscreenshot %s\nkey F3\nwait 2\nscreenshot %s\n' "$images/rooms-final.png" "$images/rooms-edges.png" > "$work/rooms.txt"
xvfb-run -a -s "-screen 0 1280x1024x24" "$viewer" "$root/scenes/rooms.gltf" --size 320x240 --script "$work/rooms.txt"

# The whole window at 960x600: the short block selected (outlined), then the reachability view
# with the hovered pixel's 5x5 drawn large in the panel.
cat > "$work/window.txt" <<SCRIPT
wait 60
click left 555 470
wait 30
window-screenshot $images/window.png
key F5
move 540 401
wait 20
window-screenshot $images/window-reachability.png
SCRIPT
xvfb-run -a -s "-screen 0 1280x1024x24" "$viewer" "$scene" --size 960x600 --script "$work/window.txt"
# The default 512x512 window: the panel folded to its title bar, the overlay in its compact form.
printf 'wait 60\nwindow-screenshot %s\n' "$images/window-512.png" > "$work/window-512.txt"
xvfb-run -a -s "-screen 0 1280x1024x24" "$viewer" "$scene" --script "$work/window-512.txt"
# Render scale: chains in a 1280x720 window while the camera orbits (a drag), rendered at the
# window's size and at half its width and height (docs/viewer.md, "Render scale").
for scale in 1 0.5; do
  printf 'key TAB\nwait 40\ndrag left 600 360 760 360 40\nwindow-screenshot %s\n' "$images/render-scale-$scale-moving.png" > "$work/scale.txt"
  xvfb-run -a -s "-screen 0 1920x1200x24" "$viewer" "$root/scenes/chains.gltf" --size 1280x720 --render-scale "$scale" --script "$work/scale.txt"
done

fi

# 2. Benchmarks: --benchmark orbits the camera a little every window frame.
machine="$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
table="| size | render scale | window fps | redraws a second | frame loop fps (median ms) | display: texture upload from the frame's PBO (median / max ms) | with glFinish (median / max ms) | input to screen (median / p90 ms) |"$'\n'"|---|---|---|---|---|---|---|---|"
for run in "512x512 1" "1920x1080 1" "1920x1080 0.75" "1920x1080 0.5"; do
  read -r size scale <<<"$run"
  out=$(xvfb-run -a -s "-screen 0 1920x1200x24" "$viewer" "$scene" --size "$size" --render-scale "$scale" --benchmark 300 --ui-fps 60)
  wfps=$(sed -n 's/^BENCHMARK_WINDOW_FPS \([0-9.]*\).*/\1/p' <<<"$out")
  redraws=$(sed -n 's/^BENCHMARK_REDRAWS \([0-9.]*\).*/\1/p' <<<"$out")
  rfps=$(sed -n 's/^BENCHMARK_RENDER_FPS \([0-9.]*\).*frame-loop ms: median \([0-9.]*\).*/\1 (\2)/p' <<<"$out")
  disp=$(sed -n 's/^BENCHMARK_DISPLAY_MS median \([0-9.]*\), max \([0-9.]*\) .*with glFinish median \([0-9.]*\), max \([0-9.]*\)/\1 \/ \2|\3 \/ \4/p' <<<"$out")
  lat=$(sed -n 's/^BENCHMARK_LATENCY_MS median \([0-9.]*\), p90 \([0-9.]*\).*/\1 \/ \2/p' <<<"$out")
  table+=$'\n'"| $size | $scale | $wfps | $redraws | $rfps | ${disp%%|*} | ${disp##*|} | $lat |"
done
block="<!-- viewer-benchmark:begin (tools/viewer-figures.sh writes this) -->"$'\n'"Measured $(date -u +%Y-%m-%d) on $machine; \`epi-viewer scenes/cornell_box.gltf --size WxH --render-scale F --benchmark 300\` under \`xvfb-run\` (Mesa llvmpipe), epi mode, direct shader, budget 0.02."$'\n\n'"$table"$'\n'"<!-- viewer-benchmark:end -->"
BLOCK="$block" /usr/bin/python3 - "$root/docs/viewer.md" <<'PY'
import os, re, sys
path = sys.argv[1]
text = open(path).read()
new = re.sub(r"<!-- viewer-benchmark:begin.*?<!-- viewer-benchmark:end -->", lambda m: os.environ["BLOCK"], text, flags=re.S)
open(path, "w").write(new)
PY
echo "wrote $images and the benchmark table of docs/viewer.md"
