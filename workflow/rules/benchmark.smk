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
        gl=gl_params,
        lighting=lighting_params,
    script:
        "../scripts/speed_accuracy.py"


# The default renderer against the exact reference at every view (worst view, p99 and MAE per surface), and
# the largest deviation of each arc curve of Figs. 21 and 28 from the exact curve.
rule renderer_validation:
    input:
        study="results/study.parquet",
    output:
        validation="results/benchmarks/{plan}/renderer_validation.parquet",
        smoothness="results/benchmarks/{plan}/arc_smoothness.parquet",
        chart=report(
            "results/benchmarks/{plan}/renderer_validation.png",
            caption="../report/renderer_validation.rst",
            category="Speed and accuracy",
        ),
    log:
        "results/logs/benchmarks/{plan}/renderer_validation.log",
    benchmark:
        "results/logs/benchmarks/{plan}/renderer_validation.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        gl=gl_params,
        lighting=lighting_params,
        render=fast_render_params,
        table_aspects=table_aspects_param,
        table_incidence=table_incidence_param,
    script:
        "../scripts/renderer_validation.py"


# The implicit rough surface (one flat quad through shaders/implicit.frag): its exact form, first-order
# correction and table (on the surfaces rule share_table tabulated) against the exact reference on every view of the
# validation surfaces, beside the fast renderer and the V-cavity facet model; and frame times of an N x N field
# drawn explicitly against one implicit quad.
rule implicit_surface:
    input:
        tables=export_share_files,
    output:
        validation="results/benchmarks/{plan}/implicit_validation.parquet",
        frames="results/benchmarks/{plan}/implicit_frames.parquet",
        maps="results/benchmarks/{plan}/implicit_maps.parquet",
        chart=report(
            "results/benchmarks/{plan}/implicit.png",
            caption="../report/implicit.rst",
            category="Speed and accuracy",
        ),
        maps_chart=report(
            "results/benchmarks/{plan}/implicit_maps.png",
            caption="../report/implicit_maps.rst",
            category="Speed and accuracy",
        ),
    log:
        "results/logs/benchmarks/{plan}/implicit.log",
    benchmark:
        "results/logs/benchmarks/{plan}/implicit.benchmark.tsv"
    priority: PRIORITY_EXPORT
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        gl=gl_params,
        lighting=lighting_params,
        exported=exported_surfaces,
    script:
        "../scripts/implicit_surface.py"


# Beyond the OpenGL equation (report.light_transport): the study's surfaces in Mitsuba 3 (render.method mitsuba),
# direct light alone against the exact reference, and what light that bounces between facets adds to the diffuse at
# the study's albedo and a physical one (docs/mitsuba.md).
rule light_transport:
    output:
        agreement="results/benchmarks/{plan}/mitsuba_agreement.parquet",
        interreflection="results/benchmarks/{plan}/interreflection.parquet",
        summary="results/benchmarks/{plan}/interreflection_summary.csv",
        chart=report(
            "results/benchmarks/{plan}/light_transport.png",
            caption="../report/light_transport.rst",
            category="Speed and accuracy",
        ),
    log:
        "results/logs/benchmarks/{plan}/light_transport.log",
    benchmark:
        "results/logs/benchmarks/{plan}/light_transport.benchmark.tsv"
    priority: PRIORITY_SCANS
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        lighting=lighting_params,
        mitsuba=mitsuba_params,
        bounces=light_transport_bounces,
        albedo=light_transport_albedo,
    script:
        "../scripts/light_transport.py"


# Random tiles (surface.kind): the random-roughness claim's statistics of each kind's mean surface against tile
# size (the tile-size choice; the claim's discs, set at surface.cells, at t 1, a 0.5, i 30), the fast renderer
# against the exact reference on random tiles and its views per second beside the regular surface's, and pictures
# of each kind.
rule random_tiles:
    output:
        convergence="results/benchmarks/{plan}/tile_convergence.parquet",
        accuracy="results/benchmarks/{plan}/random_accuracy.parquet",
        chart=report(
            "results/benchmarks/{plan}/random_tiles.png",
            caption="../report/random_tiles.rst",
            category="Speed and accuracy",
        ),
    log:
        "results/logs/benchmarks/{plan}/random_tiles.log",
    benchmark:
        "results/logs/benchmarks/{plan}/random_tiles.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        gl=gl_params,
        lighting=lighting_params,
        render=fast_tile_render_params,
        surface=tile_surface_params,
    script:
        "../scripts/random_tiles.py"


# Every view of the study's random sweeps against the exact reference (`make every-view`; not in the default
# workflow: the reference takes minutes a tile): both random kinds, their first two seeds, the random grid's
# lowest and highest corner, at the tables' incidence (common.smk's every_view_files).
rule random_every_view:
    input:
        "results/sweeps/i{incidence}/{kind}/t{truncation}_a{aspect}",
    output:
        "results/benchmarks/every_view/i{incidence}/{kind}/t{truncation}_a{aspect}_s{seed}.parquet",
    log:
        "results/logs/benchmarks/every_view/i{incidence}/{kind}/t{truncation}_a{aspect}_s{seed}.log",
    benchmark:
        "results/logs/benchmarks/every_view/i{incidence}/{kind}/t{truncation}_a{aspect}_s{seed}.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        gl=gl_params,
        surface=random_surface_params,
        incidence=incidence_param,
        lighting=lighting_params,
    script:
        "../scripts/every_view.py"


rule every_view_summary:
    input:
        every_view_files(),
    output:
        "results/benchmarks/every_view/summary.csv",
    log:
        "results/logs/benchmarks/every_view/summary.log",
    benchmark:
        "results/logs/benchmarks/every_view/summary.benchmark.tsv"
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    script:
        "../scripts/every_view_summary.py"


# the claim's regular lobes around each lobe, unrounded: the fast method at the study's azimuth step, half of it
# and 1 degree, and the exact reference at the study's (every step at the full plan), for two of the claim's
# margins and the page's table of each lobe by step (roughlight.measurements.claim_grid)
rule claim_grid:
    input:
        geometry="results/analysis/random_claim_geometry.csv",
    output:
        "results/benchmarks/{plan}/claim_grid.parquet",
    log:
        "results/logs/benchmarks/{plan}/claim_grid.log",
    benchmark:
        "results/logs/benchmarks/{plan}/claim_grid.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        gl=gl_params,
        lighting=lighting_params,
        sweep=sweep_params,
        render=random_render_params,
    script:
        "../scripts/claim_grid.py"
