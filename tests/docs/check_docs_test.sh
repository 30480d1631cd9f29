#!/usr/bin/env bash
# The docs check must pass a tree whose references hold and catch each kind
# of dead reference planted in it (as layer_check_catches_upward_include
# does for the layer check):
#   tests/docs/check_docs_test.sh CHECK WORK
set -euo pipefail
check=$1
work=$2
rm -rf "$work"
mkdir -p "$work/docs" "$work/scripts"
cd "$work"
printf 'demo:\n\ttrue\nrun: build\n\ttrue\n.PHONY: demo run\n' > Makefile
touch scripts/tool.sh
cat > docs/guide.md <<'MD'
# Guide

## Exit codes (all stages)

Back to the [README](../README.md#start).
MD
cat > README.md <<'MD'
# Start

Run `make demo`, then `make run SCENE=x OUT=y`; read [the guide](docs/guide.md)
and its [exit codes](docs/guide.md#exit-codes-all-stages); `scripts/tool.sh`
does it. `make run: not removable` is a message, `scripts/<name>.sh` a
placeholder.

```sh
make demo        # a command in a code block
```
MD
if ! out=$(python3 "$check" "$work" 2>&1); then
  echo "check_docs_test: a tree whose references hold was refused:"; echo "$out"; exit 1
fi

# One dead reference of each kind.
cat >> README.md <<'MD'

A [missing file](docs/missing.md), a [missing heading](docs/guide.md#no-such-heading),
a missing path `scripts/gone.sh`, a missing target `make nothing-here`.

```sh
make also-missing   # in a code block
```
MD
if out=$(python3 "$check" "$work" 2>&1); then
  echo "check_docs_test: dead references were not caught:"; echo "$out"; exit 1
fi
for expected in "docs/missing.md does not exist" "no heading '#no-such-heading' in docs/guide.md" \
                "\`scripts/gone.sh\`: no such file" "no target 'nothing-here'" "make also-missing: no such target" \
                "5 dead reference(s)"; do
  if ! grep -qF -- "$expected" <<<"$out"; then
    echo "check_docs_test: the report lacks '$expected':"; echo "$out"; exit 1
  fi
done
echo "check_docs_test: passes a sound tree, catches a dead link, anchor, path and make target"
