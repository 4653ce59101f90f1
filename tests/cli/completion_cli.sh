#!/usr/bin/env bash
# `lagrangian completion bash|zsh`: the scripts offer each subcommand's
# options once, the fixed choices of the options that have them, and scene
# files, models and shells where those are expected.
# The bash script is run (bash's programmable completion, driven by hand);
# the zsh script is checked against `lagrangian SUBCOMMAND --help`, and
# loaded into zsh's completion system (scripts/setup installs zsh).
# Usage: completion_cli.sh LAGRANGIAN_BINARY SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
fails=0

# shellcheck source=expect.sh
source "$(dirname "$0")/expect.sh"
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

expect 2 "completion: unknown shell 'fish' \(bash and zsh are supported\)" -- "$bin" completion fish

# The subcommands and, per subcommand, its option names, from the help texts.
subcommands=$("$bin" --help | awk '/^Subcommands:/ {on = 1; next} on && /^  [a-z]/ {print $1}')
[ -n "$subcommands" ] || fail "no subcommands in 'lagrangian --help'"
options_of() {  # SUBCOMMAND -> its option names, one a line (from its --help)
  "$bin" "$1" --help | grep -E '^ +-' | grep -oE '(^| |,)--?[a-z][a-z0-9-]*' | tr -d ' ,' | sort -u
}

# -- bash ---------------------------------------------------------------------
"$bin" completion bash > "$work/completion.bash" || fail "completion bash"
completes() {  # completes WORD... -> the candidates for the last word, joined by '|'
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _lagrangian; IFS="|"; echo "${COMPREPLY[*]}"' \
    _ "$work/completion.bash" lagrangian "$@"
}
check_completion() {  # EXPECTED WORD...
  local want=$1; shift
  local got; got=$(completes "$@")
  [ "$got" = "$want" ] && echo "ok: completing '$*'" || fail "completing '$*' gave '$got', expected '$want'"
}
check_completion "run" ru
check_completion "--no-animation" run x.toml --no-an
check_completion "--animate-to|--animate-seconds" run x.toml --anim
check_completion "--help" run x.toml --he  # once, though CLI11 lists it and it is added to every subcommand
check_completion "dopri5" run x.toml --method dop
check_completion "rk4,dopri5" bench x.toml --methods rk4,dop
check_completion "none|baumgarte|projection" bench x.toml --stabilization ""
check_completion "projection" bench x.toml --stabilization pro
check_completion "midpoint|trapezoidal" solve-bvp x.toml --rule ""
check_completion "final,energy" sweep x.toml --output final,en
check_completion "bash|zsh" completion ""
check_completion "double_pendulum" list double_p
check_completion "$src/examples/scenes/bouncing_ball.toml" run "$src/examples/scenes/bouncing_b"
check_completion "" run x.toml --rtol 1
check_completion "$src/examples/scenes/bouncing_ball.toml" run --no-plots -q "$src/examples/scenes/bouncing_b"  # after flags
mkdir -p "$work/a dir" && : > "$work/a dir/my scene.toml"
check_completion "$work/a dir/my scene.toml" run "$work/a dir/my"  # one candidate, spaces and all
check_completion "--equilibria" inspect x.toml --equi
# Every subcommand offers each of its options exactly once, and all of them.
for sub in $subcommands; do
  offered=$(completes "$sub" - | tr '|' '\n')
  dups=$(sort <<<"$offered" | uniq -d)
  [ -z "$dups" ] || fail "bash: '$sub -' offers twice: $dups"
  missing=$(comm -23 <(options_of "$sub") <(sort -u <<<"$offered"))
  [ -z "$missing" ] || fail "bash: '$sub -' lacks: $missing"
done

# -- zsh ----------------------------------------------------------------------
"$bin" completion zsh > "$work/_lagrangian" || fail "completion zsh"
zsh_script=$work/_lagrangian
[ "$(head -1 "$zsh_script")" = "#compdef lagrangian" ] || fail "zsh: the first line is not '#compdef lagrangian'"
grep -qxF '  compdef _lagrangian lagrangian' "$zsh_script" || fail "zsh: no compdef when sourced"
bash -n "$zsh_script" || fail "zsh: quotes or case/esac unbalanced (bash -n)"
if command -v zsh > /dev/null; then
  zsh -n "$zsh_script" || fail "zsh -n"
  # Loaded into a real zsh with its completion system, the script defines _lagrangian and binds it.
  zsh -fc 'autoload -Uz compinit && compinit -u -d "$2/zcompdump" && source "$1" && (( $+functions[_lagrangian] )) &&
           [[ $_comps[lagrangian] == _lagrangian ]]' _ "$zsh_script" "$work" ||
    fail "zsh: the script does not load and bind _lagrangian"
else
  echo "note: zsh is not installed; its script is checked by its text only"
fi
block_of() {  # SUBCOMMAND -> its _arguments specifications in the zsh script
  awk -v sub_="        $1)" '$0 == sub_ {on = 1; next} on && /&& ret=0 ;;$/ {print; exit} on {print}' "$zsh_script"
}
for sub in $subcommands; do
  grep -qE "^    '$sub:[^']+'$" "$zsh_script" || fail "zsh: subcommand '$sub' not listed with its description"
  block=$(block_of "$sub")
  [ -n "$block" ] || { fail "zsh: no case for '$sub'"; continue; }
  # Each option named once (an alias pair {-q,--quiet} counts each name).
  named=$(sed -nE -e "s/^ +'\([^)]*\)'\{([^}]*)\}.*/\1/p" -e "s/^ +'(\([^)]*\))?\*?(--?[a-z][a-z0-9-]*).*/\2/p" \
    <<<"$block" | tr ',' '\n' | sort)
  dups=$(uniq -d <<<"$named")
  [ -z "$dups" ] || fail "zsh: '$sub' specifies twice: $dups"
  missing=$(comm -23 <(options_of "$sub") <(sort -u <<<"$named"))
  [ -z "$missing" ] || fail "zsh: '$sub' lacks: $missing"
done
zsh_has() {  # SUBCOMMAND FIXED-STRING: the subcommand's specifications contain the string
  grep -qF -- "$2" <<<"$(block_of "$1")" && echo "ok: zsh $1 has $2" || fail "zsh: '$1' lacks $2"
}
zsh_has bench "'--stabilization=[constraint drift control]:stabilization:(none baumgarte projection)'"
zsh_has bench ":methods:_values -s , methods rk4 dopri5"
zsh_has run ":method:(rk4 dopri5 cash_karp54"
zsh_has run "event_driven)'"
zsh_has run "'--out=[output directory, overrides output.directory]:out:_files -/'"
zsh_has run ":animate-to:_files -g \"*.(mp4|webm|gif)\"'"
zsh_has run "'1:scene:_files -g \"*.toml\"'"
zsh_has run "'(--quiet -q)'{--quiet,-q}'[print only errors]'"
zsh_has run "'*--set=["
zsh_has run "'(- *)'{--help,-h}'["
zsh_has solve-bvp ":rule:(midpoint trapezoidal)'"
zsh_has sweep ":output:_values -s , output final events energy error cost wall chaos'"
zsh_has list "'1:model:(" 
zsh_has list " double_pendulum "
zsh_has completion "'1:shell:(bash zsh)'"

if [ "$fails" -ne 0 ]; then
  echo "$fails completion check(s) failed"
  exit 1
fi
echo "all completion checks passed"
