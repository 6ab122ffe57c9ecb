# The study table: every rough sweep joined to its control.


rule study_table:
    input:
        rough=rough_sweep_files(),
        random=random_ensemble_folders(),
        control=control_sweep_files(),
    output:
        "results/study.parquet",
    log:
        "results/logs/study.log",
    benchmark:
        "results/logs/study.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        random=random_sweep_files,
    script:
        "../scripts/study_table.py"
