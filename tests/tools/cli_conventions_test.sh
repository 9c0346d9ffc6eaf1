#!/usr/bin/env bash
# zbrdf's command-line conventions, through the binary:
#   1. --version and -V print what `zbrdf version` prints;
#   2. a mistyped command, global option or flag gets the closest names, exit status 2;
#   3. the completion scripts: bash's COMPREPLY for commands, prior's actions and flags; the
#      flags each command's script offers are those its --help lists (two routes to the same
#      CommandLine: describe mode and the printed help); zsh's script, where zsh exists.
#   bash cli_conventions_test.sh ZBRDF
set -euo pipefail
zbrdf=$1
fail() { echo "FAILED: $*" >&2; exit 1; }
tmp=$(mktemp -d /tmp/zbrdf-cli-test.XXXXXX)
trap 'rm -rf "$tmp"' EXIT

# 1. --version
version=$("$zbrdf" version)
[[ $version =~ ^zbrdf\ [0-9]+\.[0-9]+\.[0-9]+$ ]] || fail "zbrdf version printed '$version'"
[[ $("$zbrdf" --version) == "$version" && $("$zbrdf" -V) == "$version" ]] ||
  fail "--version: '$("$zbrdf" --version)', -V: '$("$zbrdf" -V)', version: '$version'"

# 2. Did you mean: the message and the exit status.
expect_error() {  # expect_error "ARGS" "MESSAGE"
  local status=0
  $zbrdf $1 >/dev/null 2>"$tmp/err" || status=$?
  [[ $status == 2 ]] || fail "zbrdf $1 exited with $status, not 2"
  [[ $(cat "$tmp/err") == "$2" ]] || fail "zbrdf $1 said '$(cat "$tmp/err")', not '$2'"
}
expect_error "simulat" \
  "zbrdf: unknown command 'simulat'; did you mean 'simulate'? (zbrdf --help lists them)"
expect_error "fitall x" \
  "zbrdf: unknown command 'fitall'; did you mean 'fit-all'? (zbrdf --help lists them)"
expect_error "xyzzy" "zbrdf: unknown command 'xyzzy' (zbrdf --help lists them)"
expect_error "--verison" \
  "zbrdf: unknown option '--verison'; did you mean '--version'? (zbrdf --help lists them)"
expect_error "simulate --ordr 4" \
  "zbrdf simulate: error: unknown flag --ordr; did you mean --order? (see zbrdf simulate --help)"
expect_error "prior info --jsno" \
  "zbrdf prior: error: unknown flag --jsno; did you mean --json? (see zbrdf prior info --help)"
expect_error "simulate --bogus-flag" \
  "zbrdf simulate: error: unknown flag --bogus-flag (see zbrdf simulate --help)"

# 3. bash completion, sourced as bash-completion would.
"$zbrdf" completion bash >"$tmp/zbrdf.bash"
complete_line() {  # complete_line WORD... : COMPREPLY when the cursor is on the last word
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _zbrdf
           echo "${COMPREPLY[*]}"' _ "$tmp/zbrdf.bash" "$@"
}
[[ $(complete_line zbrdf sim) == simulate ]] || fail "zbrdf sim<TAB>: '$(complete_line zbrdf sim)'"
[[ $(complete_line zbrdf simulate --or) == --order ]] ||
  fail "zbrdf simulate --or<TAB>: '$(complete_line zbrdf simulate --or)'"
[[ $(complete_line zbrdf fit) == "fit fit-all" ]] || fail "zbrdf fit<TAB>: '$(complete_line zbrdf fit)'"
[[ $(complete_line zbrdf prior "") == "build info --help" ]] ||
  fail "zbrdf prior <TAB>: '$(complete_line zbrdf prior "")'"
[[ $(complete_line zbrdf prior build --fr) == --from ]] ||
  fail "zbrdf prior build --fr<TAB>: '$(complete_line zbrdf prior build --fr)'"
# A value or a file: nothing from the script (the shell completes file names, -o default).
[[ -z $(complete_line zbrdf simulate --rig "") ]] || fail "zbrdf simulate --rig <TAB> offered words"

# Each command's (and action's) flags in the script are those of its --help.
"$zbrdf" completion commands >"$tmp/commands"
[[ $(grep -c . "$tmp/commands") -gt 20 ]] || fail "completion commands listed: $(cat "$tmp/commands")"
while IFS=$'\t' read -r words summary; do
  [[ -n $summary ]] || fail "completion commands: '$words' has no summary"
  [[ $words == prior ]] && continue  # dispatches on build|info; its help lists them, not flags
  # shellcheck disable=SC2086  # words is "prior build" for an action
  help_flags=$("$zbrdf" $words --help | sed -n 's/^  \(--[a-z0-9-]*\).*/\1/p' | sort | xargs)
  script_flags=$(complete_line zbrdf $words -- | tr ' ' '\n' | sort | xargs)
  [[ -n $help_flags && $help_flags == "$script_flags" ]] ||
    fail "zbrdf $words: --help lists '$help_flags', the completion offers '$script_flags'"
done <"$tmp/commands"
grep -q "^simulate	simulate and process" "$tmp/commands" || fail "no simulate in completion commands"
grep -q "^prior build	" "$tmp/commands" || fail "no prior build in completion commands"

# zsh: the script parses, and with zsh's _describe stubbed, offers the same words.
if command -v zsh >/dev/null; then
  "$zbrdf" completion zsh >"$tmp/_zbrdf"
  zsh -n "$tmp/_zbrdf" || fail "the zsh completion does not parse"
  zsh_offers() {  # zsh_offers WORD...: the names _describe is given for the last word
    zsh -f -c 'compdef() { :; }; _files() { :; }
               _describe() { local name=${@[-1]}; print -rl -- "${(@)${(P)name}%%:*}"; }
               source "$1"; shift; words=("$@"); CURRENT=$#; PREFIX=${words[-1]}; _zbrdf' \
      _ "$tmp/_zbrdf" "$@"
  }
  zsh_offers zbrdf sim | grep -qx simulate || fail "zsh: zbrdf sim<TAB> offers no simulate"
  zsh_offers zbrdf simulate --or | grep -qx -- --order || fail "zsh: simulate --or<TAB> has no --order"
  zsh_offers zbrdf prior "" | grep -qx build || fail "zsh: zbrdf prior <TAB> has no build"
else
  echo "zsh not found: its completion script not checked"
fi
echo "command-line conventions hold"
