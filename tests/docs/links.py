#!/usr/bin/env python3
"""The documentation holds together: the README stays a short front page (at most 200
lines), and every relative link and image in the README, docs/*.md and firmware/README.md
reaches a file and, with #anchor, a heading of it (GitHub's slugs).
Usage: links.py SOURCE_DIR"""
import glob
import os
import re
import sys

root = sys.argv[1]


def strip_code(text):
    out, fence = [], False
    for line in text.split('\n'):
        if line.lstrip().startswith('```'):
            fence = not fence
            out.append('')
            continue
        out.append('' if fence else re.sub(r'`[^`]*`', '', line))
    return '\n'.join(out)


def slugs(path):
    seen, found, fence = {}, set(), False
    for line in open(path, encoding='utf-8').read().split('\n'):
        if line.lstrip().startswith('```'):
            fence = not fence
            continue
        m = not fence and re.match(r'^(#{1,6})\s+(.*?)\s*#*\s*$', line)
        if not m:
            continue
        h = re.sub(r'[^\w\- ]', '', m.group(2).strip().lower()).replace(' ', '-')
        n = seen.get(h, 0)
        seen[h] = n + 1
        found.add(h if n == 0 else f'{h}-{n}')
    return found


readme = os.path.join(root, 'README.md')
problems = []
n_lines = sum(1 for _ in open(readme, encoding='utf-8'))
if n_lines > 200:
    problems.append(f'README.md: {n_lines} lines, a front page has at most 200')
pages = [readme, os.path.join(root, 'firmware', 'README.md')] + sorted(
    glob.glob(os.path.join(root, 'docs', '*.md')))
checked = 0
for md in pages:
    text = strip_code(open(md, encoding='utf-8').read())
    for m in re.finditer(r'!?\[[^\]]*\]\(([^)\s]+)\)', text):
        target = m.group(1)
        if re.match(r'^[a-z]+:', target):
            continue  # http:, mailto:
        checked += 1
        path, _, anchor = target.partition('#')
        full = os.path.normpath(os.path.join(os.path.dirname(md), path)) if path else md
        where = os.path.relpath(md, root)
        if not os.path.exists(full):
            problems.append(f'{where}: {target}: no such file')
        elif anchor and anchor not in slugs(full):
            problems.append(f'{where}: {target}: no heading #{anchor}')
for p in problems:
    print('FAIL:', p)
print(f'README.md: {n_lines} lines; {checked} relative links in {len(pages)} pages, '
      f'{len(problems)} problems')
sys.exit(1 if problems else 0)
