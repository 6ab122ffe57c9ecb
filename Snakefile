# roughlight: how explicitly modelled rough surfaces reflect light.
# Run the study with `snakemake --cores 2` (or `make study`); see README.md.
from snakemake.utils import min_version, validate

min_version("9.0")


configfile: "config/config.yaml"


include: "workflow/rules/common.smk"


# readable messages first (names the key and what is allowed), then the standard check
check_config(config, "workflow/schemas/config.schema.yaml")
validate(config, "workflow/schemas/config.schema.yaml")


check_results_writable()


onstart:
    acquire_run_lock()
    check_results_writable(probe=True)
    check_gl_platform()
    check_mitsuba()
    log_followed()


include: "workflow/rules/render.smk"
include: "workflow/rules/study.smk"
include: "workflow/rules/benchmark.smk"
include: "workflow/rules/stability.smk"
include: "workflow/rules/export.smk"
include: "workflow/rules/report.smk"


rule all:
    default_target: True
    input:
        "results/study.parquet",
        mesh_files(),
        random_mesh_files(),
        "reports/roughlight_report.html",
        export_files(),
