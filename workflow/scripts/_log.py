"""Logging for the workflow's scripts: to the rule's log file and to stderr."""
import logging
import sys


def setup(snakemake):
    handlers = [logging.StreamHandler(sys.stderr)]
    if snakemake.log:
        handlers.append(logging.FileHandler(snakemake.log[0], mode="w"))
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(message)s", handlers=handlers, force=True)
    return logging.getLogger(snakemake.rule).info
