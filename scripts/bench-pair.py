#!/usr/bin/env python3
"""Compare opalray binaries in alternating rounds.

    scripts/bench-pair.py OLD_BINARY NEW_BINARY [MORE_BINARIES...] [--pairs 12] [--runs 3]
        [-- BENCH ARGS...]

Runs `BINARY bench --runs R --json` for every binary, PAIRS rounds, and prints per stage the
median and fastest of each, and for each new binary the median of its per-round differences
(new − old) with how many rounds it was faster. On a shared machine whose speed drifts over
minutes, a difference within one round is measured under the same conditions; two medians
taken minutes apart are not. With `--runs 1` and more pairs the rounds are shorter, and
closer to the same conditions. The binaries run in the given order in odd rounds and in the
reverse order in even ones: the one run second in a round has an edge (the same binary run
twice, 20 rounds, one order: the second 6 ms faster in the view pass), which an even number
of rounds cancels. A measuring aid, not part of the tests; needs only Python 3.
"""
import json
import statistics
import subprocess
import sys

STAGES = ("light_pass", "view_pass", "total")


def bench(binary, runs, extra):
    out = subprocess.run(
        [binary, "bench", "--runs", str(runs), "--json", *extra],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return {s: json.loads(out)["median_s"][s] * 1000.0 for s in STAGES}


def main(argv):
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1 :]
        argv = argv[: argv.index("--")]
    args = argv[1:]
    usage = "usage: " + " ".join(line.strip() for line in __doc__.strip().splitlines()[2:4])
    pairs, runs = 12, 3
    for flag in ("--pairs", "--runs"):
        if flag in args:
            k = args.index(flag)
            try:
                value = int(args[k + 1])
            except (IndexError, ValueError):
                sys.exit(f"{flag} needs a whole number\n{usage}")
            del args[k : k + 2]
            if flag == "--pairs":
                pairs = value
            else:
                runs = value
    if len(args) < 2 or pairs < 1 or runs < 1:
        sys.exit(usage)
    results = {b: [] for b in args}
    for k in range(pairs):
        for b in args if k % 2 == 0 else reversed(args):
            results[b].append(bench(b, runs, extra))
        print(f"round {k + 1}/{pairs}", file=sys.stderr)
    old_bin, old = args[0], results[args[0]]
    for new_bin in args[1:]:
        new = results[new_bin]
        if len(args) > 2:
            print(f"{new_bin} against {old_bin}:")
        for s in STAGES:
            diffs = [n[s] - o[s] for o, n in zip(old, new)]
            faster = sum(1 for d in diffs if d < 0)
            print(
                f"{s:10}  old {statistics.median(o[s] for o in old):6.0f} ms"
                f" (fastest {min(o[s] for o in old):4.0f})"
                f"  new {statistics.median(n[s] for n in new):6.0f} ms"
                f" (fastest {min(n[s] for n in new):4.0f})"
                f"  pairs: {statistics.median(diffs):+5.0f} ms, new faster in {faster}/{pairs}"
            )


if __name__ == "__main__":
    main(sys.argv)
