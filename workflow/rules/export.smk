# The measured BRDF exported for a light from any direction (export.surfaces; docs/export.md), one surface a job: its
# table of facet shares (render.method implicit_table draws it on one quad), measured by the exact reference at the
# table's nodes (export.table) ...
rule share_table:
    output:
        shares="results/export/t{truncation}_a{aspect}/shares.npz",
        table="results/export/t{truncation}_a{aspect}/table.json",
    log:
        "results/logs/export/t{truncation}_a{aspect}_table.log",
    benchmark:
        "results/logs/export/t{truncation}_a{aspect}_table.benchmark.tsv"
    priority: PRIORITY_EXPORT
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        surface=export_surface_param,
        nodes=export_table_params,
        shadows=table_shadows_param,
    script:
        "../scripts/share_table.py"


# ... and from the table a file Mitsuba 3's own measured plugin loads, each checked against the exact reference at
# lights and views off its nodes (export.mitsuba, export.check: a change of either measures no table again). At
# priority 0, a job that fills a gap: at the table's priority it ran beside implicit_surface as soon as the table
# was done, both cores away from the regular sweeps that the study chain waits for.
rule export:
    input:
        shares="results/export/t{truncation}_a{aspect}/shares.npz",
        table="results/export/t{truncation}_a{aspect}/table.json",
    output:
        mitsuba="results/export/t{truncation}_a{aspect}/brdf.bsdf",
        check="results/export/t{truncation}_a{aspect}/check.parquet",
        summary="results/export/t{truncation}_a{aspect}/summary.csv",
    log:
        "results/logs/export/t{truncation}_a{aspect}.log",
    benchmark:
        "results/logs/export/t{truncation}_a{aspect}.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
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
