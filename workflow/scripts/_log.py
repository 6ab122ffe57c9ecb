"""Logging for the workflow's scripts: to the rule's log file and to stderr."""
import logging
import os
import resource
import sys


def setup(snakemake):
    handlers = [logging.StreamHandler(sys.stderr)]
    if snakemake.log:
        handlers.append(logging.FileHandler(snakemake.log[0], mode="w"))
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(message)s", handlers=handlers, force=True)
    return logging.getLogger(snakemake.rule).info


def end_job():
    """End a job whose outputs are written and closed: flush the logs and leave at once. The interpreter's own
    teardown (its modules; OpenGL's, llvmpipe's, pandas' and matplotlib's libraries) took 0.2-0.3 s a job, a sixth
    of a regular sweep's; nothing of the job's is left to run or write by then (issue 35). Every script's last
    line.

    Before it leaves, the job logs its peak memory (``peak memory N MB``: the largest resident set of its process
    and of the children it waited for, by ``getrusage``): Snakemake's benchmark file samples the memory now and then
    and can miss a peak (rule implicit_surface's explicit N 512 field: 873 MB, its benchmark file 400-740 MB), and
    tests/budget.py takes the larger of the two."""
    peak_kb = max(resource.getrusage(who).ru_maxrss for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    logging.getLogger("roughlight.job").info("peak memory %.0f MB", peak_kb / 1024.0)
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
