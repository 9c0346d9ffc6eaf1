#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then the INSTALLED zbrdf with a clean environment
# (no ZBRDF_DATA_DIR, HOME in the temporary folder, run from there): it finds its own data under
# PREFIX/share/zbrdf and not the source tree it was built from (basis/data_path.h), reads a bundled
# material, the default prior and a bundled rig by name, and its man pages and completion scripts
# are installed and work (README.md, Install).
#   bash install_test.sh CMAKE BUILD_DIR HELP2MAN(path, or empty if the build found none)
set -euo pipefail
cmake=$1 build=$(cd "$2" && pwd) help2man=$3

fail() { echo "FAILED: $*" >&2; exit 1; }
[[ -f $build/man-and-completion/stamp ]] ||
  fail "$build has no completion scripts or man pages yet; build everything first (cmake --build $build)"
tmp=$(mktemp -d /tmp/zbrdf-install-test.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
"$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" ||
  fail "cmake --install: $(tail -5 "$tmp/install.log")"

for f in bin/zbrdf share/zbrdf/data/priors/merl100.exr share/zbrdf/data/materials/merl/blue-acrylic.json \
    share/zbrdf/data/baselines/ngan2005-best-fits.csv share/zbrdf/rig/rigs/thesis.yaml \
    share/doc/zbrdf/design.md share/doc/zbrdf/README.md \
    share/bash-completion/completions/zbrdf share/zsh/site-functions/_zbrdf; do
  [[ -f $prefix/$f ]] || fail "$f was not installed"
done

# The installed binary, with nothing from this environment, from a folder outside the trees.
cd "$tmp"
zbrdf() { env -i PATH=/usr/bin:/bin HOME="$tmp" "$prefix/bin/zbrdf" "$@"; }

[[ $(zbrdf --version) == "$(zbrdf version)" && $(zbrdf -V) =~ ^zbrdf\ [0-9]+\.[0-9]+\.[0-9]+$ ]] ||
  fail "--version printed '$(zbrdf --version)', version '$(zbrdf version)'"

# The data root it uses is the prefix's: prior info names the default prior's path.
prior=$(zbrdf prior info --json | python3 -c "import json, sys; print(json.load(sys.stdin)['prior'])")
[[ $prior == "$prefix/share/zbrdf/data/priors/merl100.exr" ]] ||
  fail "the installed zbrdf reads the default prior from $prior, not from $prefix/share/zbrdf"

# A bundled material, evaluated by the installed zbrdf and by the build's on the same pair: the
# same numbers (the same network file, copied).
pair='0.3 0 0.3 3.14159265'
installed=$(echo "$pair" | zbrdf eval merl:blue-acrylic)
built=$(echo "$pair" | "$build/zbrdf" eval merl:blue-acrylic)
[[ -n $installed && $installed == "$built" ]] ||
  fail "eval merl:blue-acrylic: installed '$installed', built '$built'"

# A bundled rig by its name.
zbrdf design-dome --rig thesis --out "$tmp/dome" >/dev/null || fail "design-dome --rig thesis failed"
[[ -f $tmp/dome/dome-profile.csv ]] || fail "design-dome --rig thesis wrote no profile"

# Completion: the installed bash script completes commands and a command's flags.
reply=$(bash -c 'source "$1"
  COMP_WORDS=(zbrdf sim); COMP_CWORD=1; _zbrdf; echo "${COMPREPLY[*]}"
  COMP_WORDS=(zbrdf simulate --or); COMP_CWORD=2; _zbrdf; echo "${COMPREPLY[*]}"' \
  _ "$prefix/share/bash-completion/completions/zbrdf")
[[ $reply == $'simulate\n--order' ]] || fail "bash completion replied '$reply'"
if command -v zsh >/dev/null; then
  zsh -n "$prefix/share/zsh/site-functions/_zbrdf" || fail "the zsh completion does not parse"
fi

# Man pages, where the build found help2man.
if [[ -n $help2man ]]; then
  for page in zbrdf zbrdf-simulate zbrdf-prior-build zbrdf-completion; do
    [[ -f $prefix/share/man/man1/$page.1 ]] || fail "man page $page.1 was not installed"
  done
  if command -v man >/dev/null; then
    text=$(MANWIDTH=100 man -l "$prefix/share/man/man1/zbrdf-simulate.1" 2>&1) ||
      fail "man -l zbrdf-simulate.1: $text"
    [[ $text == *SYNOPSIS*"zbrdf simulate"*--order* ]] || fail "zbrdf-simulate.1 reads: $text"
  fi
else
  echo "no man pages checked: the build found no help2man"
fi
echo "installed zbrdf in $prefix works with a clean environment"
