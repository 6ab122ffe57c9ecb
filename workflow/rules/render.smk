# Sweeps: one job per surface x incidence, plus one control (flat plate) per incidence.


rule control_sweep:
    output:
        "results/sweeps/i{incidence}/control.parquet",
    params:
        surface={"truncation": 0.0, "aspect": 0.0},
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=control_lighting_params,
        method=method_param,
        render=render_params,
    log:
        "results/logs/sweeps/i{incidence}/control.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/control.benchmark.tsv"
    threads: 1
    resources:
        mem_mb=1024,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/render_sweep.py"


rule rough_sweep:
    output:
        "results/sweeps/i{incidence}/t{truncation}_a{aspect}.parquet",
    params:
        surface=surface_params,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=lighting_params,
        method=method_param,
        render=render_params,
    log:
        "results/logs/sweeps/i{incidence}/t{truncation}_a{aspect}.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/t{truncation}_a{aspect}.benchmark.tsv"
    threads: 1
    resources:
        mem_mb=1024,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/render_sweep.py"


rule surface_meshes:
    output:
        mesh_files(),
    params:
        grid=grid_params,
    log:
        "results/logs/meshes.log",
    threads: 1
    resources:
        mem_mb=512,
    conda:
        "../../envs/render.yaml"
    script:
        "../scripts/write_meshes.py"
