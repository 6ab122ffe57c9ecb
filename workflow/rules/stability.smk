# Where methods fail (`make bench`): each method against the exact reference
# as pixels per period, view elevation, incidence, shadow bias and map size,
# shininess, shading normals and the source's level (clipping at 255) vary.
# One job per measurement (both cores busy; an interrupted run keeps the
# measurements already written), then one job for the table, the safe domain
# and the chart. Not part of `rule all`: the naive baseline renders one view
# at a time.


rule stability_measurement:
    output:
        "results/stability/measurements/{measurement}.parquet",
    params:
        lighting=lighting_params,
    log:
        "results/logs/stability/{measurement}.log",
    benchmark:
        "results/logs/stability/{measurement}.benchmark.tsv"
    wildcard_constraints:
        measurement="|".join(STABILITY_MEASUREMENTS),
    threads: 1
    resources:
        mem_mb=2048,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/stability_measurement.py"


rule stability:
    input:
        stability_measurement_files(),
    output:
        table="results/stability/stability.parquet",
        safe="results/stability/safe_domain.csv",
        chart=report(
            "results/stability/stability.png",
            caption="../report/stability.rst",
            category="Where methods fail",
        ),
    params:
        lighting=lighting_params,
    log:
        "results/logs/stability/stability.log",
    benchmark:
        "results/logs/stability/stability.benchmark.tsv"
    threads: 1
    resources:
        mem_mb=2048,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/stability.py"
