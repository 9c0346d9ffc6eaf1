#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs a simulated capture of a bundled
# measured material (MERL blue-acrylic) on the thesis rig, end to end: exposure metering, 50
# basis patterns x 3 exposures, HDR merge, zonal coefficients and their error against the
# material's true coefficients; then the SH conversion, the recommended whole-hemisphere fit
# (`fit --model auto`: the prior learned from measured materials, the D-BRDF and GGX, compared by
# cross-validation; with the thesis's figure 3.3: truth | SH | fit), a material-ball preview of
# it, a 30-frame turntable under the studio map and an HTML report. Results land in
# results/blue-acrylic/ (open report.html).
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
./build/zbrdf simulate --rig rig/rigs/thesis.yaml --material merl:blue-acrylic --order 4 \
  --out "$out" "$@"
echo
./build/zbrdf convert "$out" --to sh --target sh
echo
./build/zbrdf fit "$out" --model auto --figure "$out/figure-3-3.png"
echo
./build/zbrdf preview "$out" --out "$out/ball.png"
./build/zbrdf preview "$out" --turntable 30 --environment studio --sampler smc --spp 16
./build/zbrdf report "$out"
echo
echo "Results in $out/:"
echo "  report.html      everything below on one page (open it in a browser)"
echo "  zonal.exr        zonal coefficients per basis function (any OpenEXR viewer)"
echo "  sh-sh.exr        the SH conversion, with per-exitant tables for renderers"
echo "  fit-auto.json    the recommended fit and why (cross-validated errors of every candidate)"
echo "  fit-prior.exr    the whole-hemisphere fit from the prior (docs/prior.md), with uncertainty"
echo "  fit-dbrdf.exr    the D-BRDF candidate (docs/sh-and-dbrdf-files.md); fit-*.json the reports"
echo "  figure-3-3.png   ground truth | SH of the zonal data | recommended fit"
echo "  ball.png         a material ball of the recommended fit under the built-in sky"
echo "  turntable/       a 30-frame turntable under the studio map: animation.png (animated), frames"
echo "  hdr/*.exr        the HDR image of every basis pattern"
echo "  frames/          the raw frames (16-bit TIFF), journal.jsonl, session.json"
echo "  report.json      timings and the coefficient error against the material"
