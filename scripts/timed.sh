#!/bin/sh
# Runs a command and records its wall time for ausbau-verdict:
#   scripts/timed.sh NAME DIR command [args...]
# writes DIR/NAME.seconds (one number, seconds) atomically (a temporary file
# renamed onto it), also when the command fails, and exits with the
# command's exit code. Used by pipelines/inistate.mk.
if [ $# -lt 3 ]; then
  echo "usage: $0 NAME DIR command [args...]" >&2
  exit 2
fi
name=$1
dir=$2
shift 2
mkdir -p "$dir" || exit 1
start=$(date +%s.%N)
"$@"
code=$?
end=$(date +%s.%N)
tmp="$dir/.$name.seconds.$$"
# A new file of ours (rm, then noclobber): never written through a link
# planted under the temporary's name; mv -T replaces a link at the result's
# name (to a folder too: not moved into it).
rm -f "$tmp"
(set -C; awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f\n", b - a }' > "$tmp") && mv -fT "$tmp" "$dir/$name.seconds"
exit $code
