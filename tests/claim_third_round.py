"""A third round of the random-roughness claim, planned from the second's tested seeds as its pilots
(docs/random-roughness.md, "A third round, planned"): for each test the second round left *undecided* on a
finished run's claim table, the fresh seeds that would decide it at a family level of its own, and what they cost.

    python tests/claim_third_round.py results/analysis     # a finished default run's analysis folder
    python tests/claim_third_round.py results/analysis --family 5 --reading unrounded

Reads ``random_claims.csv`` (the verdicts, the tested ensembles' means, jackknife errors and seed counts) and, for
the cost, the tested ensembles' benchmark files (``results/logs/claims/tested/...``, seconds a job over its seeds).
The seeds come from :func:`roughlight.analysis.claims.planned_seeds`, the design's own rule, with the second
round's tested readings in the pilots' place; fresh seeds, never pooled with the read ones (that would be optional
stopping). A test with no spread to plan from (a shape test whose lobe is undecided) waits on its lobe test and is
counted in the family. Reads nothing the second round has not already read; renders nothing.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from roughlight.analysis.claims import planned_seeds


def seconds_a_seed(logs: Path, kind: str, truncation: float, aspect: float, seeds: int) -> float:
    """A tested tile's seconds at one grid point, from its job's benchmark file (NaN when there is none)."""
    path = logs / "claims" / "tested" / "i30" / kind / f"t{truncation:g}_a{aspect:g}.benchmark.tsv"
    if not path.exists():
        return float("nan")
    return float(pd.read_csv(path, sep="\t")["s"].iloc[-1]) / max(int(seeds), 1)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("analysis", type=Path, help="a finished run's results/analysis")
    parser.add_argument("--family", type=int, default=None, help="tests in the third round's family (default: the "
                                                                  "undecided tests, those that wait included)")
    parser.add_argument("--reading", default="unrounded", choices=("unrounded", "8-bit"))
    parser.add_argument("--alpha", type=float, default=0.05)
    args = parser.parse_args(argv)
    claims = pd.read_csv(args.analysis / "random_claims.csv")
    open_tests = claims[(claims["reading"] == args.reading) & (claims["verdict"] == "undecided")]
    family = args.family or len(open_tests)
    level = 1.0 - args.alpha / family
    logs = args.analysis.parent / "logs"
    print(f"{len(open_tests)} undecided ({args.reading}); a family of {family} at the level {level:.4f}")
    print("| kind | t | a | test | round 2: mean, se, seeds | fresh seeds | why | seconds a seed | job-seconds |")
    print("|---|---|---|---|---|---|---|---|---|")
    total = 0.0
    for _, row in open_tests.iterrows():
        role = "lobe" if row["test"].endswith("contrast") else "shape"
        n, why = planned_seeds(row["mean"], row["se"], int(row["seeds"]), row["regular"], row["margin"], level, role)
        cost = seconds_a_seed(logs, row["kind"], row["truncation"], row["aspect"], row["seeds"])
        job = n * cost if n else float("nan")
        total += job if job == job else 0.0
        print(f"| {row['kind']} | {row['truncation']:g} | {row['aspect']:g} | {row['test']} | "
              f"{row['mean']:.3f}, {row['se']:.3f}, {int(row['seeds'])} | {n if n else '-'} | {why} | "
              f"{cost:.2f} | {job:.1f} |")
    print(f"job-seconds of the tests that can be planned: {total:.1f}")


if __name__ == "__main__":
    main()
