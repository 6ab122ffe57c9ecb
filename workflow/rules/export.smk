# The measured BRDF exported for a light from any direction (export.surfaces; docs/export.md): one surface a job,
# its table of facet shares (render.method implicit_table draws it on one quad) and a file Mitsuba 3's own
# measured plugin loads, each checked against the exact reference at lights and views off its nodes.
rule export:
    output:
        shares="results/export/t{truncation}_a{aspect}/shares.npz",
        mitsuba="results/export/t{truncation}_a{aspect}/brdf.bsdf",
        check="results/export/t{truncation}_a{aspect}/check.parquet",
        summary="results/export/t{truncation}_a{aspect}/summary.csv",
    log:
        "results/logs/export/t{truncation}_a{aspect}.log",
    benchmark:
        "results/logs/export/t{truncation}_a{aspect}.benchmark.tsv"
    priority: PRIORITY_EXPORT
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        surface=export_surface_param,
        export=export_params,
        gl=gl_params,
        lighting=lighting_params,
    script:
        "../scripts/export.py"


# Every exported surface's summary in one table, and the picture the report shows (the first surface's table over
# the hemisphere, every checked view's error).
rule export_summary:
    input:
        summaries=export_summary_files,
        checks=export_check_files,
        shares=export_share_files,
    output:
        summary="results/export/summary.csv",
        chart=report(
            "results/export/export.png",
            caption="../report/export.rst",
            category="Speed and accuracy",
        ),
    log:
        "results/logs/export/summary.log",
    benchmark:
        "results/logs/export/summary.benchmark.tsv"
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        lighting=lighting_params,
    script:
        "../scripts/export_summary.py"
