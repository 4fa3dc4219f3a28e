#!/usr/bin/env python3
"""A PsychoPy-style trial loop: a cue, a tactile stimulus through the stimulator, a yes/no
answer, a trial log (CSV).  It runs as it is on the emulator; in PsychoPy, draw the cue
with visual.TextStim and read the answer with event.waitKeys where marked.  (Debian has
no PsychoPy package, so this example uses none.)

    python3 trial_loop.py --port emu --log trials.csv           # you answer y/n
    python3 trial_loop.py --port emu --answers yes --log t.csv  # a scripted observer
"""
import argparse
import csv
import random
import sys
import time

import tactile_primaries as tp

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--port", default="emu", help="emu, or the stimulator's serial port")
parser.add_argument("--trials", type=int, default=6)
parser.add_argument("--log", default="trials.csv")
parser.add_argument("--record", help="emu only: each delivered pulse as a JSON line")
parser.add_argument("--answers", choices=["ask", "yes", "no"], default="ask")
parser.add_argument("--seed", type=int, default=1)
args = parser.parse_args()

# The stimuli: each primary's pattern at a few amplitudes, in a random order.
rng = random.Random(args.seed)
designs = {m: tp.optimize_weights(tp.Document.create(), m) for m in ("RA", "SAI", "PC")}
rates = {"RA": 30, "SAI": 200, "PC": 250}
trials = [(m, a) for m in designs for a in (0.4, 0.8)]
rng.shuffle(trials)
trials = trials[: args.trials]

with tp.Stimulator(args.port, record=args.record) as stimulator, \
        open(args.log, "w", newline="") as f:
    log = csv.writer(f)
    log.writerow(["trial", "mode", "amplitude_mA", "rate_hz", "pulses", "answer", "rt_s"])
    for k, (mode, amp) in enumerate(trials, 1):
        stim = tp.make_pulse(designs[mode], amp, rates[mode], duration_s=0.3)
        print(f"trial {k}: +", file=sys.stderr)  # PsychoPy: a fixation cross, win.flip()
        time.sleep(0.2)
        report = stimulator.deliver(stim)        # Ctrl-C stops the output first
        t0 = time.monotonic()
        if args.answers == "ask":                # PsychoPy: event.waitKeys(keyList=["y", "n"])
            answer = input(f"trial {k}: felt it? [y/n] ").strip().lower()[:1] == "y"
        else:
            answer = args.answers == "yes"
        log.writerow([k, mode, amp, rates[mode], report["pulses"], int(answer),
                      round(time.monotonic() - t0, 3)])
print(f"{len(trials)} trials logged in {args.log}", file=sys.stderr)
