# Speed against accuracy (`make bench`): every method and setting on one fixed
# set of surfaces and views, in one process. Not part of `rule all`: the naive
# baseline renders one view at a time and takes about a minute on its own.


rule speed_accuracy:
    output:
        table="results/benchmarks/speed_accuracy.parquet",
        chart=report(
            "results/benchmarks/speed_accuracy.png",
            caption="../report/speed_accuracy.rst",
            category="Speed and accuracy",
        ),
    params:
        lighting=lighting_params,
    log:
        "results/logs/benchmarks/speed_accuracy.log",
    benchmark:
        "results/logs/benchmarks/speed_accuracy.benchmark.tsv"
    threads: 1
    resources:
        mem_mb=2048,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/benchmark.py"
