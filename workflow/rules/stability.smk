# Where methods fail: each method against the exact reference as pixels per period, view
# elevation, incidence, shadow bias and map size, shininess, shading normals and the source's
# level (clipping at 255) vary. The scans run in the jobs the plan names
# (roughlight.measurements.stability.JOBS): at `full` (`make bench`) one job per scan (both
# cores busy; an interrupted run keeps the scans already written), at `quick` (the default
# workflow's report, measurements.plan) all in one job (each scan takes seconds, about what a
# job's start-up costs); then one job for the table, the safe domain and the chart. The size
# is named by the folder.


rule stability_measurement:
    output:
        "results/stability/{plan}/measurements/{measurement}.parquet",
    log:
        "results/logs/stability/{plan}/{measurement}.log",
    benchmark:
        "results/logs/stability/{plan}/{measurement}.benchmark.tsv"
    wildcard_constraints:
        measurement=STABILITY_JOBS,
    priority: PRIORITY_SCANS
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        gl=gl_params,
        lighting=lighting_params,
    script:
        "../scripts/stability_measurement.py"


rule stability:
    input:
        stability_measurement_files,
    output:
        table="results/stability/{plan}/stability.parquet",
        safe="results/stability/{plan}/safe_domain.csv",
        chart=report(
            "results/stability/{plan}/stability.png",
            caption="../report/stability.rst",
            category="Where methods fail",
        ),
    log:
        "results/logs/stability/{plan}/stability.log",
    benchmark:
        "results/logs/stability/{plan}/stability.benchmark.tsv"
    priority: PRIORITY_SCANS
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        gl=gl_params,
        lighting=lighting_params,
    script:
        "../scripts/stability.py"
