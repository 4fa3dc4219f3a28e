#!/usr/bin/env python3
"""docs/benchmarks.md keeps one current figure per row: every row of a table with a
"measured" column ends in "DATE, COMMIT" (and a note in parentheses at most), its figure
holds no date and no "later" (earlier figures go to the History section); and, in a git
clone with its history, every commit cited there and in History exists and was made on the
date stated beside it.
Usage: benchmarks.py SOURCE_DIR"""
import os
import re
import subprocess
import sys

root = sys.argv[1]
page = os.path.join(root, 'docs', 'benchmarks.md')
text = open(page, encoding='utf-8').read()
problems, rows, cited = [], 0, []
measured = False
for n, line in enumerate(text.split('\n'), 1):
    if not line.startswith('|'):
        measured = False
        continue
    cells = [c.strip() for c in re.split(r'(?<!\\)\|', line)[1:-1]]
    if cells and cells[-1] == 'measured':
        measured = True
        continue
    if not measured or set(line) <= set('|-'):
        continue
    rows += 1
    m = re.fullmatch(r'(\d{4}-\d\d-\d\d), ([0-9a-f]{7,40})( \(.*\))?', cells[-1])
    if not m:
        problems.append(f'line {n}: the measured cell is not "DATE, COMMIT": {cells[-1]}')
    else:
        cited.append((f'line {n}', m.group(1), m.group(2)))
    figure = cells[-2]
    if re.search(r'\d{4}-\d\d-\d\d|\blater\b', figure):
        problems.append(f'line {n}: the figure holds an earlier measurement (History): {figure[:80]}')
history = text.split('\n## History\n', 1)
if len(history) != 2:
    problems.append('no History section')
else:
    body = history[1].split('\n## ', 1)[0]
    for m in re.finditer(r'\((\d{4}-\d\d-\d\d), (?:[^)]*?\b)?([0-9a-f]{7,40})\b', body):
        cited.append(('History', m.group(1), m.group(2)))

git = ['git', '-C', root]
checked = 0
if (subprocess.run(git + ['rev-parse', '--git-dir'], capture_output=True).returncode == 0 and
        subprocess.run(git + ['rev-parse', '--is-shallow-repository'], capture_output=True,
                       text=True).stdout.strip() == 'false'):
    for where, date, commit in cited:
        r = subprocess.run(git + ['log', '-1', '--format=%cd', '--date=short', commit + '^{commit}'],
                           capture_output=True, text=True)
        if r.returncode != 0:
            problems.append(f'{where}: no commit {commit}')
        elif r.stdout.strip() != date:
            problems.append(f'{where}: {commit} was made on {r.stdout.strip()}, not {date}')
        checked += 1
if rows == 0:
    problems.append('no table with a "measured" column')
for p in problems:
    print('FAIL:', p)
print(f'docs/benchmarks.md: {rows} rows with a measured date and commit, '
      f'{checked} commits checked, {len(problems)} problems')
sys.exit(1 if problems else 0)
