#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs a simulated capture of a bundled
# measured material (MERL blue-acrylic) on the thesis rig, end to end: exposure metering, 50
# basis patterns x 3 exposures, HDR merge, zonal coefficients, and their error against the
# material's true coefficients. Results land in results/blue-acrylic/ (see its report.json).
#
#   bash scripts/demo.sh                 # full resolution (about 2 minutes on 2 cores)
#   bash scripts/demo.sh --preset fast   # 4x4-binned camera, quarter-size projector (~15 s)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
out=results/blue-acrylic
if [ -e "$out/session.json" ]; then
  echo "demo: $out holds the results of an earlier run; moving it to $out.previous" >&2
  rm -rf "$out.previous"
  mv "$out" "$out.previous"
fi
mkdir -p results
./build/zbrdf simulate --rig simulate/rigs/thesis.yaml --material merl:blue-acrylic --order 4 \
  --out "$out" "$@"
echo
echo "Results in $out/:"
echo "  zonal.exr     zonal coefficients per basis function (open with any OpenEXR viewer)"
echo "  hdr/*.exr     the HDR image of every basis pattern"
echo "  frames/       the raw frames (16-bit TIFF), journal.jsonl, session.json"
echo "  report.json   timings and the coefficient error against the material"
