#!/bin/sh
# The summary of a batch (make batch): one row per scene folder of OUT.
#   scripts/verdict-table.sh OUT NAME...
# Reads OUT/NAME/pipeline.exit (the pipeline's exit status, written by
# pipelines/batch.mk) and OUT/NAME/verdict.json (ausbau-verdict's layout:
# one key per line). Exits 1 when any scene is not removable or failed.
if [ $# -lt 1 ]; then
  echo "usage: $0 OUT NAME..." >&2
  exit 2
fi
out=$1
shift
# value KEY FILE: the first `"KEY": value` in FILE, quotes removed.
value() {
  sed -n "s/^[[:space:]]*\"$1\":[[:space:]]*\"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}[[:space:]]*$/\1/p" "$2" | head -n 1
}
bad=0
removable=0
errors=
printf '%-28s %-14s %14s %9s %6s %9s  %s\n' scene status max-volume waypoint part seconds path
for name in "$@"; do
  dir=$out/$name
  code=$(cat "$dir/pipeline.exit" 2>/dev/null || echo "?")
  verdict=$dir/verdict.json
  if [ -f "$verdict" ]; then
    status=$(value status "$verdict")
    max=$(value value "$verdict")
    waypoint=$(value waypoint "$verdict")
    part=$(value part "$verdict")
    seconds=$(value total_seconds "$verdict")
    csv=$(value csv "$verdict")
  else
    status=failed max=- waypoint=- part=- seconds=- csv=-
  fi
  if [ "$code" != 0 ] && [ "$status" = removable ]; then status="failed($code)"; fi
  if [ "$status" != removable ] && [ "$status" != not-removable ]; then status="failed($code)"; fi
  if [ "$status" = removable ]; then removable=$((removable + 1)); else bad=1; fi
  case $status in
    failed*) errors="$errors$name: $(grep -m 1 ': error: ' "$dir/pipeline.log" 2>/dev/null || echo 'see pipeline.log')
" ;;
  esac
  printf '%-28s %-14s %14s %9s %6s %9s  %s\n' "$name" "$status" "${max:--}" "${waypoint:--}" "${part:--}" \
    "${seconds:--}" "${csv:--}"
done
[ -n "$errors" ] && printf '%s' "$errors"
echo "batch: $removable of $# scenes removable (logs: $out/<scene>/pipeline.log)"
exit $bad
