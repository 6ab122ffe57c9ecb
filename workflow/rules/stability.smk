# Where methods fail (`make bench`): each method against the exact reference
# as pixels per period, view elevation, incidence, shadow bias and map size,
# shininess and the source's level (clipping at 255) vary. Not part of
# `rule all`: the naive baseline renders one view at a time.


rule stability:
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
    threads: 1
    resources:
        mem_mb=2048,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/stability.py"
