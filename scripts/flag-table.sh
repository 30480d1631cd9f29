#!/usr/bin/env bash
# The flag table (docs/flags.md, moved there from the README), from the executables themselves.
#
#   scripts/flag-table.sh BIN_DIR docs/flags.md            check (exit 1 on a difference)
#   scripts/flag-table.sh BIN_DIR docs/flags.md --update   rewrite the table in that file
#
# Every long flag of every ausbau-* executable (from its --help) gets one row
# between the markers <!-- flags:begin --> and <!-- flags:end -->: the flag,
# its one meaning (hand-written in docs/flags.md, kept on update; "?" for a new
# flag) and the executables that have it ("all" where every one has it).
# One row per flag is the rule "one meaning per flag": an executable whose
# flag means something else must use another name.
set -euo pipefail
bin=$1
readme=$2
mode=${3:-check}
[ -d "$bin" ] || { echo "flag-table: $bin: not a folder" >&2; exit 2; }
[ -f "$readme" ] || { echo "flag-table: $readme: no such file" >&2; exit 2; }
grep -q '<!-- flags:begin -->' "$readme" && grep -q '<!-- flags:end -->' "$readme" ||
  { echo "flag-table: $readme has no <!-- flags:begin --> / <!-- flags:end --> markers" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
executables=()
for exe in "$bin"/ausbau-*; do
  [ -x "$exe" ] && [ -f "$exe" ] || continue
  # ausbau-bench is built only where OMPL is installed (not in CI); its
  # flags follow the same table but are not checked here.
  [ "$(basename "$exe")" = ausbau-bench ] && continue
  # ausbau-run is the pipeline as a command (scripts/ausbau-run.in): its
  # arguments are the pipeline's variables, not flags.
  [ "$(basename "$exe")" = ausbau-run ] && continue
  name=$(basename "$exe")
  executables+=("$name")
  # CLI11 help lines: "  -o,--output TEXT ...", "  --force", "  !--no-verify" is printed as "--no-verify".
  "$exe" --help 2>/dev/null | grep -oE '^ +(-[a-zA-Z],)?--[a-z0-9-]+' | sed -E 's/^ +//; s/^-[a-zA-Z],//' |
    sort -u | sed "s/\$/ ${name#ausbau-}/" >> "$work/pairs"
done
count=${#executables[@]}

# The meanings kept from the file's current table: "| `--flag` | meaning | where |".
sed -n '/<!-- flags:begin -->/,/<!-- flags:end -->/p' "$readme" |
  sed -nE 's/^\| `(--[a-z0-9-]+)` \| (.*) \| [^|]* \|$/\1\t\2/p' > "$work/meanings"

{
  echo '<!-- flags:begin -->'
  echo '| flag | meaning | executables (`ausbau-`) |'
  echo '|---|---|---|'
  sort "$work/pairs" | awk -v count="$count" -v meanings="$work/meanings" '
    BEGIN { FS = " "; while ((getline line < meanings) > 0) { split(line, f, "\t"); meaning[f[1]] = f[2] } }
    { flag = $1; n[flag]++; where[flag] = (n[flag] > 1) ? where[flag] ", " $2 : $2 }
    END {
      for (flag in n) {
        m = (flag in meaning) ? meaning[flag] : "?"
        w = (n[flag] == count) ? "all" : where[flag]
        printf "| `%s` | %s | %s |\n", flag, m, w
      }
    }' | LC_ALL=C sort
  echo '<!-- flags:end -->'
} > "$work/table"

sed -n '/<!-- flags:begin -->/,/<!-- flags:end -->/p' "$readme" > "$work/current"
if [ "$mode" = --update ]; then
  awk -v table="$work/table" '
    /<!-- flags:begin -->/ { while ((getline line < table) > 0) print line; skip = 1; next }
    /<!-- flags:end -->/ { skip = 0; next }
    !skip { print }' "$readme" > "$work/readme"
  cat "$work/readme" > "$readme"
  echo "flag-table: $readme updated ($(grep -c '^| `--' "$work/table") flags of $count executables)"
  exit 0
fi
if ! diff -u "$work/current" "$work/table" > "$work/diff"; then
  echo "flag-table: the flag table in $readme differs from the executables' --help:"
  cat "$work/diff"
  echo "(run scripts/flag-table.sh $bin $readme --update, then write the meaning of any new flag instead of '?')"
  exit 1
fi
if grep -q '^| `--[a-z0-9-]*` | ? |' "$work/table"; then
  echo "flag-table: flags without a meaning in $readme:"; grep '^| `--[a-z0-9-]*` | ? |' "$work/table"; exit 1
fi
echo "flag-table: $readme lists all $(grep -c '^| `--' "$work/table") flags of $count executables, one meaning each"
