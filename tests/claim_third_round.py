"""A third round of the random-roughness claim, planned from the second's tested seeds as its pilots
(docs/random-roughness.md, "A third round"): for each test the second round left *undecided* on a finished run's
claim table, the fresh seeds that would decide it at a family level of its own, and what they cost; with ``--run``,
those seeds rendered and the round's verdicts.

    python tests/claim_third_round.py results/analysis     # a finished default run's analysis folder
    python tests/claim_third_round.py results/analysis --family 5 --reading unrounded
    python tests/claim_third_round.py results/analysis --run /tmp/third   # render the planned seeds, decide

Reads ``random_claims.csv`` (the verdicts, the tested ensembles' means, jackknife errors and seed counts) and, for
the cost, the tested ensembles' benchmark files (``results/logs/claims/tested/...``, seconds a job over its seeds).
The seeds come from :func:`roughlight.analysis.claims.planned_seeds`, the design's own rule, with the second
round's tested readings in the pilots' place; fresh seeds, never pooled with the read ones (that would be optional
stopping). A test with no spread to plan from (a shape test whose lobe is undecided) waits on its lobe test and is
counted in the family.

``--run DIR`` then renders each planned ensemble's fresh tiles (seeds :data:`THIRD_ROUND_BASE` + 1 ..., none a
pilot's or a tested tile's; built and measured as rule ``claim_sweeps`` builds and measures the tested ones, with
config/config.yaml's settings, at the claim's views, through :func:`roughlight.study.tables.run_sweep`) into
``DIR/i{incidence}/{kind}/t{t}_a{a}/s{seed}.parquet``, and decides each planned test and the tests that wait on it
with the workflow's own :func:`roughlight.analysis.steps.claim_verdict` on those tiles alone, at the third round's
family level, against the second round's margins and regular values (``random_claim_margins.csv``,
``random_claim_geometry.csv``, ``random_claim_design.csv`` of the same folder).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd

from roughlight.analysis.claims import planned_seeds

#: The third round's seeds are this + 1, + 2, ...: above the tested tiles' (from 201) and below the pilots' (501).
THIRD_ROUND_BASE = 300


def seconds_a_seed(logs: Path, kind: str, truncation: float, aspect: float, seeds: int) -> float:
    """A tested tile's seconds at one grid point, from its job's benchmark file (NaN when there is none)."""
    path = logs / "claims" / "tested" / "i30" / kind / f"t{truncation:g}_a{aspect:g}.benchmark.tsv"
    if not path.exists():
        return float("nan")
    return float(pd.read_csv(path, sep="\t")["s"].iloc[-1]) / max(int(seeds), 1)


def plan(claims: pd.DataFrame, logs: Path, reading: str = "unrounded", family: int | None = None,
         alpha: float = 0.05) -> tuple[pd.DataFrame, float]:
    """The third round's plan: a row an undecided test (``kind``, ``truncation``, ``aspect``, ``incidence``,
    ``test``, round 2's ``mean``, ``se``, ``seeds``, ``fresh`` seeds planned (0 where it waits or cannot be planned),
    ``why``, ``seconds_a_seed``, ``job_seconds``) and the family level."""
    open_tests = claims[(claims["reading"] == reading) & (claims["verdict"] == "undecided")]
    level = 1.0 - alpha / (family or len(open_tests))
    rows = []
    for _, row in open_tests.iterrows():
        role = "lobe" if row["test"].endswith("contrast") else "shape"
        n, why = planned_seeds(row["mean"], row["se"], int(row["seeds"]), row["regular"], row["margin"], level, role)
        cost = seconds_a_seed(logs, row["kind"], row["truncation"], row["aspect"], row["seeds"])
        rows.append({**{k: row[k] for k in ("kind", "truncation", "aspect", "incidence", "test", "mean", "se")},
                     "seeds": int(row["seeds"]), "fresh": int(n or 0), "why": why, "seconds_a_seed": cost,
                     "job_seconds": n * cost if n else float("nan")})
    return pd.DataFrame(rows), level


def render(planned: pd.DataFrame, analysis: Path, out: Path, log=print) -> list[Path]:
    """Render each planned ensemble's fresh tiles (the most any of its tests plans) as rule ``claim_sweeps`` renders
    the tested ones; returns the ensembles' folders."""
    import yaml

    from roughlight.analysis.claim_instrument import claim_views
    from roughlight.study import config as rl_config
    from roughlight.study import plan as rl_plan
    from roughlight.study.tables import run_sweep
    from roughlight.surfaces.roughness import make_surface

    config = rl_config.validate_config(yaml.safe_load(Path("config/config.yaml").read_text()))
    geometry = pd.read_csv(analysis / "random_claim_geometry.csv")
    sweep = rl_plan.sweep_settings(config)
    folders = []
    for (kind, t, a, incidence), part in planned.groupby(["kind", "truncation", "aspect", "incidence"]):
        n = int(part["fresh"].max())
        if n == 0:
            continue
        tested = rl_config.claim_seeds(config, kind, (t, a))
        seeds = [THIRD_ROUND_BASE + k for k in range(1, n + 1)]
        if set(seeds) & (set(tested) | set(rl_config.pilot_seeds(config))):
            raise SystemExit(f"third-round seeds {seeds[0]}..{seeds[-1]} meet the tested or pilot tiles' seeds")
        views = claim_views(geometry, (t, a, incidence), sweep["azimuth_step"], sweep["elevation_step"])
        folder = out / f"i{incidence:g}" / kind / f"t{t:g}_a{a:g}"
        folder.mkdir(parents=True, exist_ok=True)
        start = time.perf_counter()
        for seed in seeds:
            path = folder / f"s{seed}.parquet"
            if not path.exists():  # an interrupted run keeps what it rendered
                surface = make_surface(**rl_plan.surface_settings(config, kind, t, a, seed, claim=True))
                run_sweep(str(path), surface=surface, incidence=incidence, sweep=sweep,
                          lighting=rl_plan.lighting(config), method=config["render"]["method"],
                          render=rl_plan.render_settings(config, "random"), views=views)
        log(f"{kind} t {t:g}, a {a:g}: {n} fresh tiles (seeds {seeds[0]}-{seeds[-1]}, {len(views[0])} views each) "
            f"in {time.perf_counter() - start:.1f} s")
        folders.append(folder)
    return folders


def decide(planned: pd.DataFrame, level: float, analysis: Path, folders: list[Path]) -> pd.DataFrame:
    """The third round's verdicts: :func:`roughlight.analysis.steps.claim_verdict` on the fresh tiles alone, the
    planned ensembles' tests at the round's ``level``, against round 2's margins; the rows of the tests round 2
    left undecided."""
    import yaml

    from roughlight.analysis.steps import claim_verdict
    from roughlight.study import config as rl_config
    from roughlight.study import plan as rl_plan
    from roughlight.study.tables import claim_rows

    config = rl_config.validate_config(yaml.safe_load(Path("config/config.yaml").read_text()))
    sweep = rl_plan.sweep_settings(config)
    keys = ["kind", "truncation", "aspect", "incidence"]
    design = pd.read_csv(analysis / "random_claim_design.csv")
    ensembles = planned.loc[planned["fresh"] > 0, keys].drop_duplicates()
    design = design.merge(ensembles, on=keys).assign(level=level)
    table = claim_verdict(claim_rows([str(f) for f in folders]), pd.read_csv(analysis / "random_claim_geometry.csv"),
                          pd.read_csv(analysis / "random_claim_margins.csv"), design,
                          (float(sweep["azimuth_step"]), float(sweep["elevation_step"])))
    return table.merge(planned[keys + ["test"]], on=keys + ["test"])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("analysis", type=Path, help="a finished run's results/analysis")
    parser.add_argument("--family", type=int, default=None, help="tests in the third round's family (default: the "
                                                                  "undecided tests, those that wait included)")
    parser.add_argument("--reading", default="unrounded", choices=("unrounded", "8-bit"))
    parser.add_argument("--alpha", type=float, default=0.05)
    parser.add_argument("--run", type=Path, metavar="DIR", help="render the planned seeds into DIR and decide")
    args = parser.parse_args(argv)
    claims = pd.read_csv(args.analysis / "random_claims.csv")
    planned, level = plan(claims, args.analysis.parent / "logs", args.reading, args.family, args.alpha)
    print(f"{len(planned)} undecided ({args.reading}); a family of {args.family or len(planned)} at the level "
          f"{level:.4f}")
    print("| kind | t | a | test | round 2: mean, se, seeds | fresh seeds | why | seconds a seed | job-seconds |")
    print("|---|---|---|---|---|---|---|---|---|")
    for _, row in planned.iterrows():
        print(f"| {row['kind']} | {row['truncation']:g} | {row['aspect']:g} | {row['test']} | "
              f"{row['mean']:.3f}, {row['se']:.3f}, {row['seeds']} | {row['fresh'] or '-'} | {row['why']} | "
              f"{row['seconds_a_seed']:.2f} | {row['job_seconds']:.1f} |")
    print(f"job-seconds of the tests that can be planned: {planned['job_seconds'].sum():.1f}")
    if args.run is None:
        return
    folders = render(planned, args.analysis, args.run)
    verdicts = decide(planned, level, args.analysis, folders)
    print("\n| kind | t | a | test | reading | seeds | mean | se | interval | margin | regular | verdict |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for _, row in verdicts.iterrows():
        print(f"| {row['kind']} | {row['truncation']:g} | {row['aspect']:g} | {row['test']} | {row['reading']} | "
              f"{row['seeds']} | {row['mean']:.3f} | {row['se']:.3f} | [{row['low']:.3f}, {row['high']:.3f}] | "
              f"{row['margin']:.3f} | {row['regular']:.3f} | {row['verdict']} |")


if __name__ == "__main__":
    main()
