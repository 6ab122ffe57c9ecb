# Speed against accuracy: every method and setting on one fixed set of surfaces and views, in one
# process, at a size named by its folder: `quick` (the default workflow's chart, measurements.plan)
# or `full` (`make bench`).


rule speed_accuracy:
    output:
        table="results/benchmarks/{plan}/speed_accuracy.parquet",
        chart=report(
            "results/benchmarks/{plan}/speed_accuracy.png",
            caption="../report/speed_accuracy.rst",
            category="Speed and accuracy",
        ),
    log:
        "results/logs/benchmarks/{plan}/speed_accuracy.log",
    benchmark:
        "results/logs/benchmarks/{plan}/speed_accuracy.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        lighting=lighting_params,
    script:
        "../scripts/speed_accuracy.py"
