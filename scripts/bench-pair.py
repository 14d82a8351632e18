#!/usr/bin/env python3
"""Compare two opalray binaries in alternating pairs.

    scripts/bench-pair.py OLD_BINARY NEW_BINARY [--pairs 12] [--runs 3] [-- BENCH ARGS...]

Runs `BINARY bench --runs R --json` for the old and then the new binary, PAIRS times, and
prints per stage the median and fastest of each, and the median of the per-pair differences
(new − old) with how many pairs the new one was faster. On a shared machine whose speed
drifts over minutes, a difference within one pair is measured under the same conditions; two
medians taken minutes apart are not. A measuring aid, not part of the tests; needs only
Python 3.
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
    pairs, runs = 12, 3
    for flag in ("--pairs", "--runs"):
        if flag in args:
            k = args.index(flag)
            value = int(args[k + 1])
            del args[k : k + 2]
            if flag == "--pairs":
                pairs = value
            else:
                runs = value
    if len(args) != 2 or pairs < 1 or runs < 1:
        sys.exit(__doc__.strip().splitlines()[2].strip())
    old_bin, new_bin = args
    old, new = [], []
    for k in range(pairs):
        old.append(bench(old_bin, runs, extra))
        new.append(bench(new_bin, runs, extra))
        print(f"pair {k + 1}/{pairs}", file=sys.stderr)
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
