#!/usr/bin/env python3
"""The sizes docs/architecture.md keeps a reader within, over the crates' Rust sources.

    scripts/sizes.py [N]

Prints the files over 400 lines, the N longest functions (default 5; a function runs from
its `fn` line to the closing brace at the same indentation, as rustfmt writes it; those in
a file's or module's tests are marked `test`), and the `too_many_arguments` allowances.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
FN = re.compile(r"^(\s*)(pub(\([^)]*\))? )?(const )?(unsafe )?(extern \"C\" )?fn \w+")


def functions(path):
    """(lines, first line, name, in tests) of every function in `path`."""
    lines = path.read_text().split("\n")
    # A file's tests start at its first `#[cfg(test)]` item with a body; one above a
    # declaration (`mod tests;`, the tests in their own file) starts nothing here.
    tests_from = next(
        (
            i
            for i, l in enumerate(lines)
            if l.strip() == "#[cfg(test)]"
            and not lines[i + 1 : i + 2] == [] and not lines[i + 1].rstrip().endswith(";")
        ),
        len(lines),
    )
    in_tests_file = path.name == "tests.rs" or "tests" in path.parts
    for i, line in enumerate(lines):
        m = FN.match(line)
        if not m or line.rstrip().endswith(";"):
            continue
        indent = m.group(1)
        for j in range(i, len(lines)):
            if lines[j] == indent + "}" or (j == i and line.rstrip().endswith("}")):
                name = line.split("fn ", 1)[1].split("(")[0].split("<")[0]
                yield j - i + 1, i + 1, name, in_tests_file or i > tests_from
                break


def main():
    top = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    files = sorted(p for p in (ROOT / "crates").rglob("*.rs") if "target" not in p.parts)
    print("files over 400 lines:")
    for p in files:
        n = p.read_text().count("\n")
        if n > 400:
            print(f"  {n:5}  {p.relative_to(ROOT)}")
    fns = [(n, p, line, name, t) for p in files for n, line, name, t in functions(p)]
    fns.sort(key=lambda f: -f[0])
    print(f"longest functions (of {len(fns)}):")
    for n, p, line, name, t in fns[:top]:
        print(f"  {n:5}  {p.relative_to(ROOT)}:{line} {name}{'  (test)' if t else ''}")
    code = [f for f in fns if not f[4]]
    print(f"longest outside tests: {code[0][0]} lines, {code[0][1].relative_to(ROOT)}:{code[0][2]} {code[0][3]}")
    print(f"functions over 80 lines outside tests: {sum(1 for f in code if f[0] > 80)}")
    allows = sum(p.read_text().count("too_many_arguments") for p in files)
    print(f"too_many_arguments allowances: {allows}")


if __name__ == "__main__":
    main()
