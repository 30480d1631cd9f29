#!/usr/bin/env python3
"""No dead reference in the docs (issue 32 item 5).

  tests/docs/check_docs.py ROOT

Reads ROOT/README.md, ROOT/ARCHITECTURE.md and ROOT/docs/*.md and fails
(exit 1, one line per finding as file:line: what) when
  - a relative markdown link [text](target) names a file that is not there,
  - a link's #anchor is no heading of its target file (GitHub's slugs),
  - a path in backticks that starts with one of the repository's top folders
    (scripts/, pipelines/, stages/, ...) is not there,
  - `make TARGET` (in backticks or a code block) names no target of the top
    Makefile.
Placeholders are not paths: anything with <, *, $, {, ... or a space in it
is skipped, as are paths under OUT/ or build/ (made by a run).
Only the standard library: it runs before anything is built.
"""
import os
import re
import sys

TOP_FOLDERS = ("scripts", "pipelines", "stages", "common", "tests", "docs", "schemas", "bench", "scenes",
               "data", "cmake", "fuzz", ".ci")


def slug(heading):
    """GitHub's anchor of a heading: lower case, markup and punctuation
    dropped (letters, digits, '-', '_' and spaces kept), spaces to '-'."""
    text = re.sub(r"`|\*\*|\[([^\]]*)\]\([^)]*\)", lambda m: m.group(1) or "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen = {}
        found = set()
        in_code = False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.startswith("```"):
                    in_code = not in_code
                    continue
                m = None if in_code else re.match(r"#{1,6} +(.*?) *#*$", line.rstrip("\n"))
                if m:
                    base = slug(m.group(1))
                    n = seen.get(base, 0)
                    seen[base] = n + 1
                    found.add(base if n == 0 else f"{base}-{n}")
        cache[path] = found
    return cache[path]


def make_targets(root):
    targets = set()
    with open(os.path.join(root, "Makefile"), encoding="utf-8") as f:
        for line in f:
            m = re.match(r"^([A-Za-z0-9_.-][A-Za-z0-9_. -]*?)\s*:(?!=)", line)
            if m and not line.startswith("\t"):
                targets.update(t for t in m.group(1).split() if not t.startswith("."))
    return targets


def make_mentions(text):
    """The target of each `make ...` command: the first word after make that
    is no option and no VAR=value; none for `make -f other.mk` or `make -C`."""
    for m in re.finditer(r"(?<![\w-])make((?: +[^\s`;|&#]+)*)", text):
        words = m.group(1).split()
        if words and words[0].startswith(("-f", "-C")):  # another Makefile or folder
            continue
        for w in words:
            if w.startswith("-") or "=" in w:
                continue
            if not w.endswith(":"):  # `make run: not removable` is a message, not a command
                yield w
            break


def is_placeholder(path):
    return any(c in path for c in "<>*${} ") or "..." in path


def check_file(root, rel, targets, problems):
    path = os.path.join(root, rel)
    here = os.path.dirname(path)
    in_code = False
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for number, line in enumerate(lines, 1):
        where = f"{rel}:{number}"
        if line.startswith("```"):
            in_code = not in_code
            continue
        if in_code:
            # Commands in code blocks: only the make targets are checked
            # (paths there are examples: a user's scene, an output folder).
            if re.match(r"\s*(make|AUSBAU_\w+=\S+ make)\b", line):
                for target in make_mentions(line.split("#", 1)[0]):
                    if target not in targets:
                        problems.append(f"{where}: make {target}: no such target in the top Makefile")
            continue
        for m in re.finditer(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)", line):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition("#")
            linked = os.path.normpath(os.path.join(here, file_part)) if file_part else path
            if not os.path.exists(linked):
                problems.append(f"{where}: link to {target}: {file_part} does not exist")
                continue
            if anchor and linked.endswith(".md") and anchor not in anchors(linked):
                problems.append(f"{where}: link to {target}: no heading '#{anchor}' in {os.path.relpath(linked, root)}")
        for m in re.finditer(r"`([^`]+)`", line):
            code = m.group(1)
            if code.startswith("make ") or " make " in code:
                for target in make_mentions(code):
                    if target not in targets:
                        problems.append(f"{where}: `{code}`: no target '{target}' in the top Makefile")
                continue
            candidate = re.sub(r":\d+(-\d+)?$", "", code)  # file.cpp:103-111
            if is_placeholder(candidate) or candidate.split("/")[0] not in TOP_FOLDERS or "/" not in candidate:
                continue
            if not os.path.exists(os.path.join(root, candidate)):
                problems.append(f"{where}: `{code}`: no such file or folder in the repository")
    # A link or path split over two lines is not seen; the docs keep them on one.


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    files = [f for f in ("README.md", "ARCHITECTURE.md") if os.path.exists(os.path.join(root, f))]
    docs = os.path.join(root, "docs")
    if os.path.isdir(docs):
        files += sorted(os.path.join("docs", f) for f in os.listdir(docs) if f.endswith(".md"))
    targets = make_targets(root)
    problems = []
    for rel in files:
        check_file(root, rel, targets, problems)
    for p in problems:
        print(p)
    if problems:
        print(f"check_docs: {len(problems)} dead reference(s) in {len(files)} files")
        return 1
    print(f"check_docs: {len(files)} files, no dead reference")
    return 0


if __name__ == "__main__":
    sys.exit(main())
