#!/usr/bin/env python3
"""A PsychoPy-style trial loop: a cue, a tactile stimulus through the stimulator, a yes/no
answer, a trial log (CSV).  It runs as it is on the emulator; in PsychoPy, draw the cue
with visual.TextStim and read the answer with event.waitKeys where marked.  (Debian has
no PsychoPy package, so this example uses none.)

    python3 trial_loop.py --port emu --log trials.csv           # you answer y, n or q
    python3 trial_loop.py --port emu --answers yes --log t.csv  # every answer "yes"

q (or the end of the answers) ends the loop after logging that trial as "quit", exit 1;
Ctrl-C stops the output at once (the Stimulator does) and exits 130.  Either way the log
holds every trial answered.
"""
import argparse
import csv
import random
import sys
import time

import tactile_primaries as tp

PROGRAM = "trial_loop.py"

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--port", default="emu", help="emu, or the stimulator's serial port")
parser.add_argument("--trials", type=int, default=6)
parser.add_argument("--trial-duration", type=float, default=0.3, help="each stimulus, s")
parser.add_argument("--log", default="trials.csv")
parser.add_argument("--record", help="emu only: each delivered pulse as a JSON line")
parser.add_argument("--answers", choices=["ask", "yes", "no"], default="ask")
parser.add_argument("--seed", type=int, default=1)
args = parser.parse_args()

ANSWERS = {"y": "yes", "yes": "yes", "n": "no", "no": "no", "q": "quit", "quit": "quit"}


def ask(k):
    """The answer to trial k, "yes", "no" or "quit", and what gave it ("the user (q)", "the
    end of the answers"); asked again until it is one of them."""
    if args.answers != "ask":
        return args.answers, "--answers"
    while True:  # PsychoPy: event.waitKeys(keyList=["y", "n", "q"])
        try:
            word = input(f"trial {k}: felt it? [y/n, q to stop] ").strip().lower()
        except EOFError:
            return "quit", "the end of the answers"
        if word in ANSWERS:
            return ANSWERS[word], f"the user ({word})"
        print(f"'{word}': answer y, n or q", file=sys.stderr)


# The stimuli: each primary's pattern at a few amplitudes, in a random order.
rng = random.Random(args.seed)
designs = {m: tp.optimize_weights(tp.Document.create(), m) for m in ("RA", "SAI", "PC")}
rates = {"RA": 30, "SAI": 200, "PC": 250}
trials = [(m, a) for m in designs for a in (0.4, 0.8)]
rng.shuffle(trials)
trials = trials[: args.trials]

logged, k, delivering = 0, 0, False
try:
    with tp.Stimulator(args.port, record=args.record) as stimulator, \
            open(args.log, "w", newline="") as f:
        log = csv.writer(f)
        log.writerow(["trial", "mode", "amplitude_mA", "rate_hz", "pulses", "answer", "rt_s"])
        for k, (mode, amp) in enumerate(trials, 1):
            stim = tp.make_pulse(designs[mode], amp, rates[mode], duration_s=args.trial_duration)
            print(f"trial {k}: +", file=sys.stderr)  # PsychoPy: a fixation cross, win.flip()
            time.sleep(0.2)
            delivering = True
            report = stimulator.deliver(stim)        # Ctrl-C stops the output first
            delivering = False
            t0 = time.monotonic()
            answer, by = ask(k)
            log.writerow([k, mode, amp, rates[mode], report["pulses"], answer,
                          round(time.monotonic() - t0, 3)])
            f.flush()
            logged += 1
            if answer == "quit":
                break
except KeyboardInterrupt:
    where = "during trial {}; output stopped" if delivering else "at trial {}; nothing running"
    print(f"{PROGRAM}: interrupted (Ctrl-C) {where.format(k)}; {logged} trials logged in "
          f"{args.log}", file=sys.stderr)
    sys.exit(130)
if logged and answer == "quit":
    print(f"{PROGRAM}: stopped by {by} after trial {k}; {logged} trials logged in {args.log}",
          file=sys.stderr)
    sys.exit(1)
print(f"{logged} trials logged in {args.log}", file=sys.stderr)
