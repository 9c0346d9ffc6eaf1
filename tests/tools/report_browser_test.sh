#!/usr/bin/env bash
# `zbrdf report` in a real browser (issue 18): headless Chromium opens a session's report.html
# and a folder's index.html, as a person would, and this checks what it shows:
#   1. every <img> loaded (complete, with a natural width);
#   2. no text, title or alt reads NaN, nan, inf or Infinity (the raw metadata folded in
#      <details> included);
#   3. the answer lies on the first screen (1280x800): the balls, the verdict, the fit and the
#      errors table end above 800 px and left of 1280 px, and the page does not scroll sideways;
#   4. the fitted session's turntable (zbrdf preview --turntable) is on its page and loads;
#   5. the index has one row per session, found one and two levels down, each linking to a
#      report.html that exists, and `--json` lists the pages written.
# The pages carry no script; the checks run in a copy with one appended, which writes its
# findings into the DOM that --dump-dom prints. Screenshots of both first screens are left in
# OUTDIR for a person to look at. Exit 77 (skipped) where Chromium is not installed.
#   bash report_browser_test.sh ZBRDF SOURCE_DIR OUTDIR
set -euo pipefail
zbrdf=$1
src=$2
out=$3
fail() { echo "FAILED: $*" >&2; exit 1; }

browser=""
for candidate in chromium chromium-browser google-chrome; do
  if command -v "$candidate" >/dev/null; then browser=$candidate; break; fi
done
if [[ -z $browser ]]; then
  echo "SKIPPED: no Chromium (chromium, chromium-browser or google-chrome) on PATH; install it" \
       "with apt-get install chromium (scripts/setup.sh does) to check the report in a browser"
  exit 77
fi

tmp=$(mktemp -d /tmp/zbrdf-report-browser.XXXXXX)
cleanup() {
  # Chromium exits after --dump-dom and --screenshot; a helper left behind by a crash would hold
  # our profile folder open: end those (ours only, by their id).
  local pids
  pids=$(pgrep -f -- "--user-data-dir=$tmp/profile" || true)
  for pid in $pids; do kill "$pid" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap cleanup EXIT
mkdir -p "$out" "$tmp/home"

# Chromium, headless, with its profile, home and caches in $tmp, nothing fetched from anywhere.
run_browser() {  # run_browser ARGS... (the page last)
  HOME=$tmp/home XDG_CONFIG_HOME=$tmp/home XDG_CACHE_HOME=$tmp/home \
    timeout 60 "$browser" --headless --no-sandbox --disable-gpu --no-first-run \
    --disable-extensions --disable-background-networking --disable-sync --hide-scrollbars \
    --user-data-dir="$tmp/profile" --window-size=1280,800 "$@" 2>>"$tmp/browser.log" ||
    { cat "$tmp/browser.log" >&2; fail "$browser $* exited with $?"; }
}

# Two small simulated sessions (order 2, fast preset): a fitted one, and one without a fit two
# levels down (its page says so; the index finds it).
sessions=$tmp/sessions
simulate() {  # simulate MATERIAL FOLDER
  "$zbrdf" simulate --rig "$src/rig/rigs/thesis.yaml" --material "$1" --order 2 --preset fast \
    --no-hdr-images --truth-samples 256 --out "$2" >"$tmp/simulate.log" 2>&1 ||
    { cat "$tmp/simulate.log" >&2; fail "zbrdf simulate $1"; }
}
simulate 'ggx:alpha=0.3,F0=0.04,kd=0.2' "$sessions/ggx"
simulate 'lambert:0.5' "$sessions/more/lambert"
"$zbrdf" fit "$sessions/ggx" --model auto --candidates prior,ggx >"$tmp/fit.log" 2>&1 ||
  { cat "$tmp/fit.log" >&2; fail "zbrdf fit"; }
# A short turntable (issue 19): the report embeds it as an animated PNG the browser must load.
"$zbrdf" preview "$sessions/ggx" --turntable 4 --size 48 --spp 2 --sampler smc \
  --environment studio >"$tmp/turntable.log" 2>&1 ||
  { cat "$tmp/turntable.log" >&2; fail "zbrdf preview --turntable"; }

"$zbrdf" report "$sessions/ggx" --size 128 --spp 4 >/dev/null
"$zbrdf" report "$sessions" --size 128 --spp 4 --json >"$tmp/index.json"
python3 - "$tmp/index.json" "$sessions" <<'EOF' || fail "zbrdf report --json on the folder"
import json, sys
j = json.load(open(sys.argv[1]))
root = sys.argv[2]
assert j["index"] == root + "/index.html", j
# The fitted session's page was up to date (written above); the other one is written now.
assert j["kept"] == [root + "/ggx/report.html"], j
assert j["written"] == [root + "/more/lambert/report.html"], j
assert j["pages"] == [j["index"]] + j["written"] and j["failed"] == [], j
EOF

# The check, appended to a copy of a page: its findings go into <pre id="zbrdf-check">.
cat >"$tmp/check.js" <<'EOF'
<script>
window.addEventListener('load', () => {
  const lines = [];
  const images = [...document.images];
  const broken = images.filter(i => !(i.complete && i.naturalWidth > 0));
  lines.push('images ' + images.length + ' broken ' + broken.length);
  const bad = /\b(NaN|nan|inf|Infinity)\b/;
  const texts = [];
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  while (walker.nextNode()) {
    if (walker.currentNode.parentNode.nodeName !== 'SCRIPT') texts.push(walker.currentNode.data);
  }
  document.querySelectorAll('[title],[alt]').forEach(e => {
    texts.push(e.getAttribute('title') || '', e.getAttribute('alt') || '');
  });
  const hit = texts.map(t => t.match(bad) ? t.substr(Math.max(0, t.match(bad).index - 50), 100)
                                          : null).find(t => t !== null);
  lines.push('nan ' + (hit === undefined ? 'none' : JSON.stringify(hit)));
  lines.push('scroll-width ' + document.documentElement.scrollWidth);
  for (const id of ['summary', 'ball-fit', 'ball-truth', 'verdict', 'fit', 'errors',
                    'turntable-animation']) {
    const e = document.getElementById(id);
    if (!e) { lines.push('element ' + id + ' missing'); continue; }
    const r = e.getBoundingClientRect();
    lines.push('element ' + id + ' bottom ' + Math.ceil(r.bottom) + ' right ' + Math.ceil(r.right));
  }
  lines.push('rows ' + document.querySelectorAll('tr.session').length);
  const pre = document.createElement('pre');
  pre.id = 'zbrdf-check';
  pre.textContent = lines.join('\n');
  document.body.appendChild(pre);
});
</script>
EOF
check_page() {  # check_page PAGE NAME: prints the check's lines
  local copy="$(dirname "$1")/.browser-check-$2.html"
  cat "$1" "$tmp/check.js" >"$copy"
  run_browser --virtual-time-budget=5000 --dump-dom "file://$copy" >"$tmp/$2.dom"
  rm -f "$copy"
  sed -n '/<pre id="zbrdf-check">/,/<\/pre>/p' "$tmp/$2.dom" | sed 's/<[^>]*>//g' >"$tmp/$2.check"
  [[ -s $tmp/$2.check ]] || fail "$2: the check did not run in $browser (no zbrdf-check in the DOM)"
  run_browser --screenshot="$out/$2-first-screen.png" "file://$1" >/dev/null
}
expect() {  # expect NAME REGEX WHAT
  grep -Eq "$2" "$tmp/$1.check" || fail "$1: $3; the browser saw: $(tr '\n' ';' <"$tmp/$1.check")"
}
# Also the page's source, outside the images' base64: no NaN anywhere, closed <details> included.
no_nan_in_source() {  # no_nan_in_source PAGE
  if sed -E 's/base64,[A-Za-z0-9+\/=]+//g; s/"thumbnail_png":"[^"]*"//' "$1" |
      grep -Eo '.{0,40}\b(NaN|nan|inf|Infinity)\b.{0,40}' >"$tmp/nan.txt"; then
    fail "$1 reads NaN or inf: $(head -3 "$tmp/nan.txt")"
  fi
}

# The session's page.
check_page "$sessions/ggx/report.html" report
expect report '^images ([1-9][0-9]*) broken 0$' "every image loads"
expect report '^nan none$' "no text reads NaN or inf"
expect report '^scroll-width (1[0-2][0-9][0-9]|[0-9]{1,3})$' "the page is no wider than 1280 px"
for id in summary ball-fit ball-truth verdict fit errors; do
  expect report "^element $id bottom ([0-7]?[0-9]?[0-9]|800) right ([0-9]{1,3}|1[01][0-9][0-9]|12[0-7][0-9]|1280)$" \
    "$id lies on the first 1280x800 screen"
done
expect report '^element turntable-animation bottom [0-9]+ right [0-9]+$' \
  "the turntable is on the page (an animated PNG; 'every image loads' covers it)"
no_nan_in_source "$sessions/ggx/report.html"
no_nan_in_source "$sessions/more/lambert/report.html"

# The index.
check_page "$sessions/index.html" index
expect index '^images 1 broken 0$' "the fitted session's ball loads (the other has no BRDF yet)"
expect index '^nan none$' "no text reads NaN or inf"
expect index '^rows 2$' "one row per session"
no_nan_in_source "$sessions/index.html"
links=$(grep -Eo 'href="[^"]*report\.html"' "$sessions/index.html" | sed 's/^href="//; s/"$//' |
        sort -u)
[[ $(echo "$links" | wc -l) == 2 ]] || fail "the index links $(echo "$links" | wc -l) reports, not 2"
for link in $links; do
  [[ -f $sessions/$link ]] || fail "the index links $link, which does not exist"
done
for png in report index; do
  [[ -s $out/$png-first-screen.png ]] || fail "no screenshot $out/$png-first-screen.png"
done
echo "report and index pages pass in $browser ($("$browser" --version 2>/dev/null | head -1));" \
     "first screens in $out/"
