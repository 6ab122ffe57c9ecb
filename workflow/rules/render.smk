# Sweeps: one job per surface x incidence, plus one control (flat plate) per incidence.


rule control_sweep:
    output:
        "results/sweeps/i{incidence}/control.parquet",
    log:
        "results/logs/sweeps/i{incidence}/control.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/control.benchmark.tsv"
    priority: PRIORITY_SWEEPS
    group:
        "sweeps"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        gl=gl_params,
        surface=rl_plan.CONTROL_SURFACE,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=control_lighting_params,
        method=method_param,
        render=render_params,
    script:
        "../scripts/sweep.py"


rule rough_sweep:
    output:
        "results/sweeps/i{incidence}/t{truncation}_a{aspect}.parquet",
    log:
        "results/logs/sweeps/i{incidence}/t{truncation}_a{aspect}.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/t{truncation}_a{aspect}.benchmark.tsv"
    priority: PRIORITY_SWEEPS
    group:
        "sweeps"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        gl=gl_params,
        surface=surface_params,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=lighting_params,
        method=method_param,
        render=render_params,
    script:
        "../scripts/sweep.py"


rule random_sweep:
    output:
        "results/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}_s{seed}.parquet",
    log:
        "results/logs/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}_s{seed}.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}_s{seed}.benchmark.tsv"
    priority: PRIORITY_TILE_SWEEPS
    group:
        "sweeps"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        gl=gl_params,
        surface=random_surface_params,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=lighting_params,
        method=method_param,
        render=random_render_params,
    script:
        "../scripts/sweep.py"


rule surface_meshes:
    output:
        mesh_files(),
        random_mesh_files(),
    log:
        "results/logs/meshes.log",
    benchmark:
        "results/logs/meshes.benchmark.tsv"
    priority: PRIORITY_SWEEPS
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=512,
    params:
        surfaces=mesh_params,
    script:
        "../scripts/surface_meshes.py"
