#!/usr/bin/env python3
"""The source layout keeps its layers (docs/layout.md, "Layers"): every #include of a
project header in lib/, tools/ and firmware/ goes to the including folder itself or to a
folder its row in the table may include; the table's graph has no cycle; and no function
in lib/ is longer than 120 lines unless the table "Longer functions" names it and says why
(function extents from universal-ctags).

Usage: layers.py SOURCE_DIR       (exit 1 and one line per fault; 0 and a summary)
"""
import os
import re
import subprocess
import sys

MAX_LINES = 120
INCLUDE = re.compile(r'^\s*#\s*include\s+"([A-Za-z0-9_]+)/[^"]+"', re.M)


def table_after(text, heading, may_be_empty=False):
    """The rows (lists of cells) of the first table after the heading line, without its
    header row."""
    at = text.find("\n" + heading + "\n")
    if at < 0:
        sys.exit(f"layers: docs/layout.md has no heading '{heading}'")
    rows = []
    for line in text[at + len(heading) + 2:].splitlines():
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not all(re.fullmatch(r":?-+:?", c) for c in cells):
                rows.append(cells)
        elif rows:
            break
    if len(rows) < (1 if may_be_empty else 2):
        sys.exit(f"layers: no table after '{heading}' in docs/layout.md")
    return rows[1:]  # without the header row


def names(cell):
    """`core/`, `device/` -> {'core', 'device'}; '—' -> set()."""
    return {n.strip("/") for n in re.findall(r"`([^`]+)`", cell)}


def layers(text):
    allowed = {}
    for row in table_after(text, "## Layers"):
        folder = names(row[0])
        if len(folder) != 1 or len(row) < 3:
            sys.exit(f"layers: a row of the Layers table does not name one folder: {row}")
        allowed[folder.pop()] = names(row[-1])
    return allowed


def cycle(allowed):
    """A cycle of the graph 'may include', as a list, or None."""
    state = {}

    def visit(n, path):
        state[n] = 1
        for m in sorted(allowed.get(n, ())):
            if m == n:
                continue
            if state.get(m) == 1:
                return path + [n, m]
            if m not in state:
                found = visit(m, path + [n])
                if found:
                    return found
        state[n] = 2
        return None

    for n in sorted(allowed):
        if n not in state:
            found = visit(n, [])
            if found:
                return found
    return None


def sources(root, top):
    for base, dirs, files in os.walk(os.path.join(root, top)):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d != "build")
        for f in sorted(files):
            if f.endswith((".hpp", ".cpp", ".h", ".c", ".cc")):
                yield os.path.join(base, f)


def folder_of(root, path):
    rel = os.path.relpath(path, root).split(os.sep)
    return rel[1] if rel[0] == "lib" else rel[0]


def include_faults(root, allowed, lib_folders):
    faults, files = [], 0
    for top in ("lib", "tools", "firmware"):
        for path in sources(root, top):
            here = folder_of(root, path)
            if top == "lib" and path.count(os.sep) - root.count(os.sep) < 2:
                continue  # lib/*.in and the like
            if here not in allowed:
                faults.append(f"{os.path.relpath(path, root)}: folder '{here}' is not in the Layers table")
                continue
            files += 1
            with open(path, encoding="utf-8") as f:
                text = f.read()
            for m in INCLUDE.finditer(text):
                target = m.group(1)
                if target == here or target not in lib_folders:
                    continue
                if target not in allowed[here]:
                    line = text.count("\n", 0, m.start()) + 1
                    faults.append(f"{os.path.relpath(path, root)}:{line}: '{here}' includes "
                                  f"{m.group(0).strip()} from '{target}', which it may not")
    return faults, files


def long_functions(root, text):
    excused = {}
    for row in table_after(text, "### Longer functions", may_be_empty=True):
        for n in names(row[0]):
            excused[n] = row[-1]
    try:
        out = subprocess.run(
            ["ctags", "-R", "--languages=C++", "--kinds-C++=f", "--fields=+ne", "-x",
             "--_xformat=%{line} %{end} %N %F", os.path.join(root, "lib")],
            check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"layers: universal-ctags failed ({e}); scripts/setup installs it")
    faults, count = [], 0
    for line in out.splitlines():
        first, last, name, path = line.split(" ", 3)
        if not last.isdigit():
            continue
        count += 1
        n = int(last) - int(first) + 1
        rel = os.path.relpath(path, root)
        if n > MAX_LINES and f"{rel}:{name}" not in excused and name not in excused:
            faults.append(f"{rel}:{first}: {name} is {n} lines (at most {MAX_LINES}, or a row "
                          "in docs/layout.md's Longer functions saying why)")
    return faults, count


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    with open(os.path.join(root, "docs", "layout.md"), encoding="utf-8") as f:
        text = f.read()
    allowed = layers(text)
    lib_folders = {d for d in os.listdir(os.path.join(root, "lib"))
                   if os.path.isdir(os.path.join(root, "lib", d))}
    faults = []
    missing = sorted(lib_folders - set(allowed))
    if missing:
        faults.append(f"docs/layout.md's Layers table lacks {', '.join(missing)}")
    found = cycle(allowed)
    if found:
        faults.append("the Layers table has a cycle: " + " -> ".join(found))
    inc, files = include_faults(root, allowed, lib_folders)
    fun, functions = long_functions(root, text)
    faults += inc + fun
    for fault in faults:
        print("layers: " + fault)
    if faults:
        return 1
    print(f"layers: {files} files keep the {len(allowed)} layers; {functions} functions in "
          f"lib/ at most {MAX_LINES} lines or excused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
