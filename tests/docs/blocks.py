#!/usr/bin/env python3
"""The fenced code blocks of a Markdown page, in order, each written to OUT_DIR/NN.LANG
(LANG: sh, python, or out for a block without a language: a program's output).
Prints one line per block: NN LANG.
Usage: blocks.py PAGE.md OUT_DIR"""
import os
import sys

page, out = sys.argv[1], sys.argv[2]
blocks, lang, lines = [], None, []
for line in open(page, encoding='utf-8').read().split('\n'):
    fence = line.lstrip().startswith('```')
    if lang is None and fence:
        lang, lines = line.strip()[3:].strip() or 'out', []
    elif lang is not None and fence:
        blocks.append((lang, lines))
        lang = None
    elif lang is not None:
        lines.append(line)
if lang is not None:
    sys.exit(f'{page}: a code block is not closed')
os.makedirs(out, exist_ok=True)
for n, (lang, lines) in enumerate(blocks, 1):
    with open(os.path.join(out, f'{n:02d}.{lang}'), 'w', encoding='utf-8') as f:
        f.write('\n'.join(lines) + '\n')
    print(f'{n:02d} {lang}')
