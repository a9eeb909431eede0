#!/usr/bin/env python3
"""Extracts every ```cpp fenced block of the given Markdown files into a C++ source file, for tests/docs.

Conventions (CONTRIBUTING.md, "C++ in the documentation"):
  * a block with `int main(` is a program: compiled as written and run by ctest (exit 0 expected);
  * `<!-- snippet: compile-only -->` on the line before the fence: a program compiled but not run;
  * `<!-- snippet: fragment -->` before the fence: statements, wrapped in a function body inside namespace rome;
    its `#include` lines are moved above the function, and tests/docs/snippet_prelude.h is included first;
  * `<!-- snippet: fragment setup=NAME -->`: the same, with tests/docs/setup/NAME.inc pasted at the top of the body
    (the declarations the fragment uses but does not show).
A block with no main and no marker is an error naming the file and line. #line directives make a compiler error name
the Markdown file and line. Writes OUT_DIR/<name>.cc (only when its text changed) and OUT_DIR/snippets.cmake.
usage: extract_snippets.py SOURCE_DIR OUT_DIR FILE.md...
"""
import os
import re
import sys

MARKER = re.compile(r"^<!--\s*snippet:\s*(program|compile-only|fragment)((?:\s+\w+=\S+)*)\s*-->\s*$")


def fail(message):
    sys.stderr.write("extract_snippets.py: " + message + "\n")
    sys.exit(1)


def blocks(path):
    """Yields (first body line number, body lines, marker kind or None, options) of each ```cpp block."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].strip() == "```cpp":
            kind, options = None, {}
            j = i - 1
            while j >= 0 and lines[j].strip() == "":
                j -= 1
            if j >= 0 and lines[j].strip().startswith("<!--") and "snippet" in lines[j]:
                m = MARKER.match(lines[j].strip())
                if not m:
                    fail("%s:%d: unknown snippet marker %r (expected <!-- snippet: program|compile-only|fragment "
                         "[setup=NAME] -->)" % (path, j + 1, lines[j].strip()))
                kind = m.group(1)
                for opt in m.group(2).split():
                    key, value = opt.split("=", 1)
                    if key != "setup":
                        fail("%s:%d: unknown snippet option %r (known: setup)" % (path, j + 1, key))
                    options[key] = value
            end = i + 1
            while end < len(lines) and lines[end].strip() != "```":
                end += 1
            if end == len(lines):
                fail("%s:%d: the ```cpp block is not closed" % (path, i + 1))
            yield i + 2, lines[i + 1:end], kind, options
            i = end
        i += 1


def render(source_dir, path, first_line, body, kind, options):
    has_main = any(re.search(r"\bint\s+main\s*\(", line) for line in body)
    if kind is None:
        if not has_main:
            fail("%s:%d: a ```cpp block with no main needs <!-- snippet: fragment --> on the line before its fence"
                 % (path, first_line - 1))
        kind = "program"
    if kind in ("program", "compile-only"):
        if not has_main:
            fail("%s:%d: a snippet marked %s has no main" % (path, first_line - 1, kind))
        return kind, '#line %d "%s"\n' % (first_line, path) + "\n".join(body) + "\n"
    if has_main:
        fail("%s:%d: a fragment has a main; leave the marker out" % (path, first_line - 1))
    includes, statements = [], []
    for number, line in enumerate(body, first_line):
        (includes if line.lstrip().startswith("#include") else statements).append((number, line))
    out = ['#include "tests/docs/snippet_prelude.h"']
    for number, line in includes:
        out += ['#line %d "%s"' % (number, path), line]
    out += ["namespace rome {", "[[maybe_unused]] void DocumentationFragment() {"]
    if "setup" in options:
        setup = os.path.join(source_dir, "tests", "docs", "setup", options["setup"] + ".inc")
        if not os.path.isfile(setup):
            fail("%s:%d: setup=%s: no file %s" % (path, first_line - 1, options["setup"], setup))
        out += ['#line 1 "%s"' % setup, open(setup, encoding="utf-8").read().rstrip("\n")]
    for number, line in statements:
        out += ['#line %d "%s"' % (number, path), line]
    out += ["}", "}  // namespace rome", "int main() { return 0; }  // a fragment is compiled, not run", ""]
    return kind, "\n".join(out)


def main():
    if len(sys.argv) < 4:
        fail("usage: extract_snippets.py SOURCE_DIR OUT_DIR FILE.md...")
    source_dir, out_dir = sys.argv[1], sys.argv[2]
    os.makedirs(out_dir, exist_ok=True)
    manifest = []
    for path in sys.argv[3:]:
        rel = os.path.relpath(path, source_dir)
        stem = re.sub(r"[^A-Za-z0-9]+", "_", os.path.splitext(rel)[0]).strip("_").lower()
        for k, (first_line, body, kind, options) in enumerate(blocks(path), 1):
            kind, text = render(source_dir, os.path.abspath(path), first_line, body, kind, options)
            name = "docs_snippet_%s_%d" % (stem, k)
            target = os.path.join(out_dir, name + ".cc")
            if not os.path.exists(target) or open(target, encoding="utf-8").read() != text:
                with open(target, "w", encoding="utf-8") as f:
                    f.write(text)
            manifest.append((name, kind, "%s:%d" % (rel, first_line - 1)))
    text = "# Written by tests/docs/extract_snippets.py: one entry per ```cpp block of the documentation.\n"
    text += "set(ROME_DOC_SNIPPETS %s)\n" % " ".join(n for n, _, _ in manifest)
    for name, kind, origin in manifest:
        text += "set(%s_KIND %s)\nset(%s_ORIGIN \"%s\")\n" % (name, kind, name, origin)
    with open(os.path.join(out_dir, "snippets.cmake"), "w", encoding="utf-8") as f:
        f.write(text)


if __name__ == "__main__":
    main()
