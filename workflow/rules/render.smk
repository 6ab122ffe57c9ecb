# Sweeps: one job a truncation and incidence (its sweeps at every grid aspect), one a random kind's ensemble at a
# grid point and incidence (a folder, a file a seed in it), and one control (flat plate) per incidence. Every sweep
# job keeps what it measures in the sweep store and takes from it what it holds (roughlight.study.sweep_store), so
# that a job rerun for a new aspect or seed renders only the new sweeps. The sweep files' format (`format`,
# roughlight.study.tables.SWEEP_FORMAT) is a param, so that a sweep written in an earlier format (without the
# columns the study table now carries) is measured again, and is part of the store's key.


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
        surfaces=[rl_plan.CONTROL_SURFACE],
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=control_lighting_params,
        method=method_param,
        render=render_params,
        store=rl_sweep_store.STORE,
        format=rl_tables.SWEEP_FORMAT,
    script:
        "../scripts/sweep.py"


rule rough_sweeps:
    output:
        rough_row_files(),
    log:
        "results/logs/sweeps/i{incidence}/t{truncation}.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/t{truncation}.benchmark.tsv"
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
        surfaces=rough_row_surfaces,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=lighting_params,
        method=method_param,
        render=render_params,
        store=rl_sweep_store.STORE,
        format=rl_tables.SWEEP_FORMAT,
    script:
        "../scripts/sweep.py"


rule random_sweeps:
    output:
        directory("results/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}"),
    log:
        "results/logs/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}.log",
    benchmark:
        "results/logs/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}.benchmark.tsv"
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
        surfaces=random_ensemble_surfaces,
        files=random_ensemble_files,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=lighting_params,
        method=method_param,
        render=random_render_params,
        store=rl_sweep_store.STORE,
        format=rl_tables.SWEEP_FORMAT,
    script:
        "../scripts/sweep.py"


# the random-roughness claim's tiles at a grid point, built at claims.cells and measured at the claim's views
# alone (the views around its lobes, from rule claim_discs' geometry): a random kind's pilots (claims.pilots,
# which plan the test) or its tested tiles (claims.seeds)
rule claim_sweeps:
    input:
        geometry="results/analysis/random_claim_geometry.csv",
    output:
        directory("results/claims/{role}/i{incidence}/{kind}/t{truncation}_a{aspect}"),
    log:
        "results/logs/claims/{role}/i{incidence}/{kind}/t{truncation}_a{aspect}.log",
    benchmark:
        "results/logs/claims/{role}/i{incidence}/{kind}/t{truncation}_a{aspect}.benchmark.tsv"
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
        surfaces=claim_ensemble_surfaces,
        files=claim_ensemble_files,
        incidence=incidence_param,
        sweep=sweep_params,
        lighting=lighting_params,
        method=method_param,
        render=random_render_params,
        store=rl_sweep_store.STORE,
        format=rl_tables.SWEEP_FORMAT,
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
