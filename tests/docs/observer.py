#!/usr/bin/env python3
"""A scripted observer for calibrate --responses -: reads calibrate's prompts on stdin
("trial N: SAI at (4, 4), 0.05 mA ... felt it? [y/n] "), answers on stdout: "felt it?"
yes at or above the primary's hidden threshold, "too strong?" yes at or above its hidden
comfort limit.  Usage: observer.py P:THRESHOLD:COMFORT ... (mA)"""
import re
import sys

hidden = {}
for arg in sys.argv[1:]:
    name, threshold, comfort = arg.split(':')
    hidden[name] = (float(threshold), float(comfort))
prompt = re.compile(r'trial \d+: (\w+) at \([^)]*\), ([0-9.e+-]+) mA \.\.\. (felt it|too strong)\? \[y/n\] $')
text = ''
while True:
    c = sys.stdin.read(1)  # the prompt ends without a newline: read it a character at a time
    if not c:
        break
    text = '' if c == '\n' else text + c
    m = prompt.search(text)
    if m:
        threshold, comfort = hidden[m.group(1)]
        level = float(m.group(2))
        yes = level >= (threshold if m.group(3) == 'felt it' else comfort)
        sys.stdout.write('y\n' if yes else 'n\n')
        sys.stdout.flush()
        text = ''
