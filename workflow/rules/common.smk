# Helpers shared by the rules: grid expansion, wildcard <-> config value, params.
import os

try:
    from roughlight.study import config as rl_config
    from roughlight.study import runs as rl_runs
    from roughlight.study import plan as rl_plan
    from roughlight.study import pilots as rl_pilots
    from roughlight.study import sweep_store as rl_sweep_store
    from roughlight.study import tables as rl_tables
    from roughlight.report import registry as rl_registry
    from roughlight.report import sections as rl_sections
    from roughlight.measurements import stability as rl_stability
except (
    ImportError
) as exc:  # the package is installed by `make setup` (pip install -e .)
    raise WorkflowError(
        "the roughlight package is not importable: run `make setup` (or `pip install -e .` "
        f"in the environment that runs snakemake) first ({exc})"
    )


wildcard_constraints:
    plan="quick|full|smoke",
    incidence=r"[0-9][0-9.e+-]*",
    truncation=r"[0-9][0-9.e+-]*",
    aspect=r"[0-9][0-9.e+-]*",
    kind="random_pyramids|random_heightfield",
    seed=r"[1-9][0-9]*",
    role="pilots|tested",


# Job order on a workstation (Snakemake runs the ready job of highest priority first): the sweeps, then the chain
# from the study table to the figures, which runs one job at a time, so that the benchmarks and scans (which
# no sweep waits for) fill the other core while it runs, instead of leaving a core idle at the end.
# Among the sweeps the random tiles' go first: the longest sweep jobs (a heightfield ensemble's seven seeds took
# 9-17 s in two default runs, a truncation's row of regular sweeps 3-7 s; issue 46),
# so that the short regular sweeps even out the two cores at the end instead of one tile sweep running alone.
# The share table and the implicit surface's check of it (a chain of about 40 s, needing no sweep) go with the
# regular sweeps: at priority 0, with no input, the greedy scheduler (the largest inputs first) left them to run
# alone at the end of the default run, one core idle for half a minute (issue 46); the export's Mitsuba file and
# checks (rule export, 7 s) fill a gap.
# The claim's chain from the study table (its discs, tested tiles, pilots' readings, design and analysis_random) is the
# study chain's too: at priority 0 its discs waited 41 s behind the figures and the benchmarks, and its last job ran
# next to the end (issue 57). The stability scans, a chain of two jobs that needs nothing, start first among the
# jobs no sweep waits for: at priority 0 (no input: the greedy scheduler's last choice) they ran alone at the end
# of the default run, one core idle for 16 s (issue 57). So does light transport, the longest job nothing but the
# page waits for (about 20 s): at priority 0 it started last, beside the page's last figures, and ran alone for 20 s
# in both default runs after the share table became a job of its own (issue 58).
PRIORITY_SWEEPS = 1
PRIORITY_TILE_SWEEPS = 2
PRIORITY_STUDY_CHAIN = 2
PRIORITY_EXPORT = 1
PRIORITY_SCANS = 1


# the keys left unset that follow the grid, one line each (roughlight.study.config.follow_grid): logged at the start
# of a run and shown in the report
FOLLOWED = []


def check_config(config, schema):
    """Validate the config with one readable line per problem; stop before any job runs. The keys that follow
    the grid take their values here (FOLLOWED says which)."""
    try:
        rl_config.validate_config(config, schema, notes=FOLLOWED)
    except rl_config.ConfigError as exc:
        raise WorkflowError(str(exc))


def log_followed():
    """Say in the run's log which keys followed the grid and the values they took."""
    from snakemake.logging import logger

    for line in FOLLOWED:
        logger.info(f"config: {line}")


def followed_params(wildcards):
    """The keys that followed the grid, as lines for the report."""
    return list(FOLLOWED)


def check_results_writable(directory="results", probe=False):
    """Stop before any job if results/ cannot be written (one message, nothing touched): looks while the
    workflow is parsed, and with `probe` writes a probe file at the start of a real run
    (roughlight.study.runs.results_problem)."""
    problem = rl_runs.results_problem(directory, probe=probe)
    if problem:
        raise WorkflowError(rl_runs.not_writable_message(directory, problem))


def check_gl_platform():
    """Stop before any job if the chosen OpenGL platform (render.platform: every renderer and picture) is missing
    or broken: libOSMesa for osmesa, libEGL with a device for egl."""
    from snakemake.logging import logger

    from roughlight.render.gl import egl, osmesa

    try:
        if config["render"]["platform"] == "egl":
            logger.info(
                f"OpenGL through EGL: {egl.check_egl(config['render']['egl_device'])}"
            )
        else:
            osmesa.check_osmesa()
    except (osmesa.OSMesaUnavailable, egl.EGLUnavailable) as exc:
        raise WorkflowError(str(exc))


def check_mitsuba():
    """Stop before any job if Mitsuba is needed (render.method mitsuba, or report.light_transport) and missing;
    else log the variant it renders in (a fallback named with what is missing) and where its kernels are cached.
    """
    from snakemake.logging import logger

    from roughlight.render.mitsuba import MitsubaUnavailable, check_mitsuba as check

    needed = (
        config["render"]["method"] == "mitsuba"
        or config["report"]["light_transport"]["enabled"]
    )
    if not needed:
        return
    try:
        logger.info(check(config["render"]["mitsuba"]["variant"]))
    except MitsubaUnavailable as exc:
        raise WorkflowError(str(exc))


# The sweeps, meshes and their settings are the study's plan (roughlight.study.plan), which tests/report_chain.py
# calls too: the builders here hand it the config and turn wildcards into grid values.


def _value(key, text):
    """The configured grid value whose label is `text` (exact, not re-parsed)."""
    for value in rl_plan.grid(config, key):
        if rl_config.label(value) == text:
            return value
    raise WorkflowError(f"{key} {text!r} is not in config grid.{key}")


def rough_sweep_files():
    """One sweep per grid point (truncation x aspect) and incidence."""
    return rl_plan.sweep_files(config, "rough")


def rough_row_files():
    """The outputs of one rough_sweeps job, a truncation's sweeps at every grid aspect (wildcards
    incidence and truncation)."""
    return rl_plan.rough_row_files(config)


def random_sweep_files(wildcards=None):
    """One sweep per random surface (surface.kind x surface.random_grid x surface.seeds) and incidence, each in
    its ensemble's folder (random_ensemble_folders)."""
    return rl_plan.sweep_files(config, "random")


def random_ensemble_folders():
    """The folders of the random_sweeps jobs: a random kind's ensemble at a random grid point and incidence."""
    return rl_plan.ensemble_folders(config)


def control_sweep_files():
    """One control (the flat plate) per incidence."""
    return rl_plan.sweep_files(config, "control")


def every_view_files():
    """`make every-view`: the study's sweeps of each random kind's first two seeds at the random grid's
    lowest and highest corner, at the tables' incidence, each against the reference at every view.
    """
    return rl_plan.every_view_files(config)


def random_mesh_files():
    """One PLY per random tile, its kind and seed in the name."""
    return rl_plan.random_mesh_files(config)


def mesh_files():
    """One PLY per grid point, and the control's."""
    return rl_plan.mesh_files(config)


def random_surface_params(wildcards):
    """A random tile's kind, grid point, seed, and how tiles are built (surface.cells, surface.spread)."""
    return rl_plan.surface_settings(
        config,
        wildcards.kind,
        _value("truncation", wildcards.truncation),
        _value("aspect", wildcards.aspect),
        int(wildcards.seed),
    )


def _ensemble(wildcards, role=None):
    """The kind, truncation, aspect and seeds of a random_sweeps job's ensemble (role: a claim_sweeps job's, its
    pilots or its tested seeds)."""
    t, a = _value("truncation", wildcards.truncation), _value(
        "aspect", wildcards.aspect
    )
    seeds = (
        rl_config.seeds(config, wildcards.kind, (t, a))
        if role is None
        else rl_config.claim_seeds(config, wildcards.kind, (t, a), role)
    )
    return (wildcards.kind, t, a, seeds)


def random_ensemble_surfaces(wildcards):
    """A random_sweeps job's surfaces: its ensemble's tiles, a seed each (random_surface_params)."""
    kind, t, a, seeds = _ensemble(wildcards)
    return [rl_plan.surface_settings(config, kind, t, a, seed) for seed in seeds]


def random_ensemble_files(wildcards):
    """A random_sweeps job's sweep files, in its folder, in the order of random_ensemble_surfaces."""
    kind, t, a, seeds = _ensemble(wildcards)
    folder = rl_plan.ensemble_folder(kind, t, a, wildcards.incidence)
    return [rl_plan.ensemble_member(folder, seed) for seed in seeds]


def claim_ensemble_surfaces(wildcards):
    """A claim_sweeps job's surfaces: its ensemble's pilot or tested tiles (wildcard role), a seed each, built
    at claims.cells."""
    kind, t, a, seeds = _ensemble(wildcards, wildcards.role)
    return [
        rl_plan.surface_settings(config, kind, t, a, seed, claim=True) for seed in seeds
    ]


def claim_ensemble_files(wildcards):
    """A claim_sweeps job's sweep files, in its folder under results/claims/{role}, in the order of its surfaces."""
    kind, t, a, seeds = _ensemble(wildcards, wildcards.role)
    folder = rl_plan.ensemble_folder(
        kind, t, a, wildcards.incidence, rl_plan.claim_folder(wildcards.role)
    )
    return [rl_plan.ensemble_member(folder, seed) for seed in seeds]


def claim_ensemble_folders(role):
    """The folders of the claim_sweeps jobs in role (pilots or tested): a random kind's claim ensemble at a random
    grid point and incidence; the pilots only of the ensembles claims.registered_pilots does not hold.
    """
    if role == "pilots":
        return rl_pilots.rendered_folders(config)
    return rl_plan.ensemble_folders(config, role)


def _registered_file(key):
    """claims.<key>, a registered table's path as an input list (none: [])."""
    path = rl_config.claims(config).get(key)
    return [path] if path else []


def registered_pilots_file(wildcards):
    """claims.registered_pilots, the pilots' registered readings (none: [])."""
    return _registered_file("registered_pilots")


def registered_round_file(name):
    """An input function: claims.registered_{name}_round, the claim's later round of that name ("third" ...
    "eighth") as registered (none: [])."""

    def registered(wildcards):
        return _registered_file(f"registered_{name}_round")

    return registered


def claim_measurement_params(wildcards):
    """What the claim's tiles are measured with, for the registered third round's key
    (roughlight.study.plan.claim_measurement)."""
    return rl_plan.claim_measurement(config)


def pilot_keys(wildcards):
    """Every claim ensemble's pilots with the digest of their settings (roughlight.study.pilots.pilot_key)."""
    return rl_pilots.pilot_keys(config)


def random_surface_settings(wildcards):
    """surface.cells and surface.spread (how random tiles are built) and the claim's tiles (claims.cells,
    claims.pilots), for the report's text."""
    return rl_config.page_surface_settings(config)


def rough_row_surfaces(wildcards):
    """The regular surfaces of a truncation at every grid aspect, in the order of rough_row_files."""
    return rl_plan.rough_row_surfaces(
        config, _value("truncation", wildcards.truncation)
    )


def incidence_param(wildcards):
    return _value("incidence", wildcards.incidence)


def sweep_params(wildcards):
    return rl_plan.sweep_settings(config)


def lighting_params(wildcards):
    return rl_plan.lighting(config)


def control_lighting_params(wildcards):
    """The plate casts no shadows: the shadows switch does not touch the control."""
    return rl_plan.lighting(config, "control")


def method_param(wildcards):
    return config["render"]["method"]


def gl_params(wildcards):
    """The OpenGL platform a rendering job uses (render.platform, render.egl_device): workflow/scripts/_gl.py."""
    return {key: config["render"][key] for key in ("platform", "egl_device")}


def render_params(wildcards):
    """The fast renderer's knobs; empty for the reference, which they do not affect."""
    return rl_plan.render_settings(config)


def random_render_params(wildcards):
    """The fast renderer's knobs with those of random tiles (render.random_tiles); empty for the reference."""
    return rl_plan.render_settings(config, "random")


def fast_render_params(wildcards):
    """The fast renderer's knobs as configured (whatever render.method the study uses)."""
    return rl_config.render_settings_from_config(config)


def fast_tile_render_params(wildcards):
    """The fast renderer's knobs for random tiles as configured (whatever render.method the study uses)."""
    return rl_config.render_settings_from_config(config, random_tiles=True)


def tile_surface_params(wildcards):
    """How the study builds random tiles (surface.cells, surface.spread): the tiles rule random_tiles measures and
    the tile size its discs are set from."""
    return rl_config.random_surface_settings(config)


def table_aspects_param(wildcards):
    """The aspects of Tables 1-2 and of the arc figures (report.table_aspects)."""
    return rl_config.report_settings(config)["table_aspects"]


def table_incidence_param(wildcards):
    return rl_config.report_settings(config)["table_incidence"]


def mesh_params(wildcards):
    """Every mesh file's surface (rl_plan.meshes): a changed grid, seed or tile setting rewrites the meshes."""
    return rl_plan.meshes(config)


# the stability scans' jobs of every plan (roughlight.measurements.stability.JOBS: at quick one job for all the
# scans, at full one a scan); importing roughlight.measurements.stability loads no OpenGL
STABILITY_JOBS = "|".join(dict.fromkeys(sum(rl_stability.JOBS.values(), ())))


def stability_measurement_files(wildcards):
    """The scans' files of a plan: one per job of roughlight.measurements.stability.JOBS."""
    return [
        f"results/stability/{wildcards.plan}/measurements/{job}.parquet"
        for job in rl_stability.JOBS[wildcards.plan]
    ]


def measurement_plan(wildcards=None):
    """The size of the speed/accuracy benchmark and the stability scans (measurements.plan): it names their folder."""
    return config["measurements"]["plan"]


def claim_grid_file(wildcards):
    """The claim's regular lobes measured around each lobe at measurements.plan (rule claim_grid)."""
    return f"results/benchmarks/{measurement_plan()}/claim_grid.parquet"


def explorer_budget(wildcards):
    """report.explorer.budget: the bytes the explorer's data may take in the page."""
    return int(config["report"]["explorer"]["budget"])


def page_code(wildcards):
    """A digest of the page's own code (roughlight.report but its figures: sections, templates, captions): a
    change to how the page is written reruns rule report_html, whose code trigger sees its script alone.
    """
    return rl_registry.page_code_digest()


def report_inputs(wildcards):
    """The page's inputs (report_html): the inputs every section of the page declares (roughlight.report.sections),
    for the sections config switches on (each section's switch: report.speed_accuracy, report.implicit,
    report.stability, report.light_transport.enabled, report.explorer.enabled, surface.kind; never which files
    exist), the measurements at measurements.plan; each
    named by its file's stem (a chart: its stem and _png), as the rule that writes it names it and as the page's
    sections take it.
    """
    return rl_sections.inputs(config, measurement_plan())


def mitsuba_params(wildcards):
    """The mitsuba method's config keys (render.mitsuba), as plain types."""
    return rl_config.mitsuba_settings_from_config(config)


def light_transport_bounces(wildcards):
    """How many times light bounces in report.light_transport's measurement."""
    return int(config["report"]["light_transport"]["bounces"])


def light_transport_albedo(wildcards):
    """The physical albedo report.light_transport measures beside the study's diffuse reflectance."""
    return float(config["report"]["light_transport"]["albedo"])


def export_files():
    """Every file rules share_table and export write for export.surfaces, and export_summary's table and picture
    ([] when none is exported)."""
    files = rl_plan.export_files(config)
    return (
        files + ["results/export/summary.csv", "results/export/export.png"]
        if files
        else []
    )


def export_summary_files(wildcards):
    """Every exported surface's summary (rule export)."""
    return rl_plan.export_files(config, ["summary"])


def export_check_files(wildcards):
    """Every exported surface's check (rule export)."""
    return rl_plan.export_files(config, ["check"])


def export_share_files(wildcards):
    """Every exported surface's share table (rule share_table)."""
    return rl_plan.export_files(config, ["shares"])


def table_shadows_param(wildcards):
    """Whether the study's surfaces cast shadows: the one lighting setting a share table depends on (its shares
    are geometry; the facets' values come from the lighting where the table is read)."""
    return bool(rl_plan.lighting(config)["shadows"])


def export_surface_param(wildcards):
    """The export.surfaces pair the job's wildcards name: [truncation, aspect]."""
    for t, a in rl_config.export_surfaces(config):
        if (rl_config.label(t), rl_config.label(a)) == (
            wildcards.truncation,
            wildcards.aspect,
        ):
            return [t, a]
    raise WorkflowError(
        f"t{wildcards.truncation}_a{wildcards.aspect} is not in config export.surfaces"
    )


def exported_surfaces(wildcards):
    """export.surfaces as [truncation, aspect] lists, in the order of export_share_files."""
    return [[t, a] for t, a in rl_config.export_surfaces(config)]


def export_table_params(wildcards):
    """export.table (defaults filled), as plain types: the share table's nodes (rule share_table)."""
    return rl_config.export_settings(config)["table"]


def export_params(wildcards):
    """export.mitsuba and export.check (defaults filled), as plain types (rule export)."""
    settings = rl_config.export_settings(config)
    return {"mitsuba": settings["mitsuba"], "check": settings["check"]}


def report_settings(wildcards):
    """The `report:` section of the config (validated, defaults filled), as plain types."""
    return rl_config.report_settings(config)


def report_keys(*keys):
    """A rule's params: the `report:` settings `keys` alone, so that a change of any other report setting (a
    figure's incidences, the table aspects) does not rerun a rule that never reads it.
    """

    def settings(wildcards):
        full = rl_config.report_settings(config)
        return {key: full[key] for key in keys}

    return settings


def claim_settings(wildcards):
    """The random-roughness claim's design (`claims:`) and each ensemble's tested seeds, as plain types."""
    return rl_config.claim_settings(config)


def figure_outputs(drawn_by):
    """The `report()` outputs of the registry's figures the rule `drawn_by` draws (figures, render_figures), by
    name."""
    return {
        figure.name: report(
            figure.path,
            caption=figure.caption_file,
            category="Figures",
            subcategory=rl_registry.SUBCATEGORIES[figure.section],
        )
        for figure in rl_registry.figures(rule=drawn_by)
    }


# One run at a time in a directory, and a killed run never blocks the next: the workflow holds an
# OS-level lock (flock) on .snakemake/roughlight.lock from its start (onstart, so dry runs, --lint and
# runs with nothing to do never take it) until its process ends (roughlight.study.runs). Job processes and
# cluster jobs run without hooks and never take it.
_run_lock = []


def acquire_run_lock():
    """Take the directory's run lock or stop at once, naming the run that holds it; nothing is touched."""
    import sys

    try:
        _run_lock.append(rl_runs.acquire_run_lock(rl_runs.RUN_LOCK, " ".join(sys.argv)))
    except rl_runs.RunLocked as exc:
        raise WorkflowError(str(exc))
