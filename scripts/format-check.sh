#!/usr/bin/env bash
# The C++ style check of .ci/run (`make format-check`): clang-format 14 with
# the checkout's .clang-format, --dry-run --Werror, over every C++ source git
# tracks (common/, stages/, tests/, bench/, fuzz/, ...). Exit 1 and the
# differences on a file that is not formatted.
#
# scripts/format-pending.txt lists the files not formatted when the check was
# introduced (issue 32): they were being edited by others, and reformatting
# them then would have clashed with that work. They are skipped, and a file
# on the list that is formatted by now is reported, so the list only shrinks:
# run `clang-format-14 -i FILE` on a listed file when you next change it and
# take it off the list.
#   scripts/format-check.sh            check
#   scripts/format-check.sh --list     print the files that differ (all, the
#                                      pending ones included), check nothing
set -euo pipefail
cd "$(dirname "$0")/.."
format=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$format" ]; then
  echo "format-check: error: clang-format not found (scripts/install-deps.sh format)" >&2
  exit 2
fi
# The .clang-format was written for clang-format 14; another version formats
# some constructs differently and would fail formatted files.
if ! "$format" --version | grep -q 'version 14\.'; then
  echo "format-check: error: $format is not clang-format 14 ($("$format" --version))" >&2
  exit 2
fi
mapfile -t files < <(git ls-files '*.cpp' '*.cc' '*.h' '*.hpp')
if [ "${1:-}" = "--list" ]; then
  for f in "${files[@]}"; do "$format" --dry-run --Werror "$f" >/dev/null 2>&1 || echo "$f"; done
  exit 0
fi
pending=$(grep -v '^#' scripts/format-pending.txt | sed '/^$/d' || true)
failed=0
checked=0
for f in "${files[@]}"; do
  if grep -qxF "$f" <<<"$pending"; then
    if "$format" --dry-run --Werror "$f" >/dev/null 2>&1; then
      echo "format-check: $f is formatted now: take it off scripts/format-pending.txt" >&2
      failed=1
    fi
    continue
  fi
  checked=$((checked + 1))
  if ! "$format" --dry-run --Werror "$f"; then
    failed=1
  fi
done
if [ "$failed" -ne 0 ]; then
  echo "format-check: failed: run clang-format-14 -i on the files above (.clang-format)" >&2
  exit 1
fi
echo "format-check: $checked files formatted ($(grep -c . <<<"$pending" || true) pending in scripts/format-pending.txt)"
