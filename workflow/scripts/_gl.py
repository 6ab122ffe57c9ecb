"""The OpenGL platform and the renderers' threads of a rendering job, set before anything loads OpenGL.

``render.platform`` (``osmesa`` or ``egl``) and ``render.egl_device`` reach the job through the rule's
``params.gl`` (so a changed platform reruns what it renders); they win over whatever the environment says.
"""
import os


def threads(snakemake):
    """The renderers' threads of a job, from its rule's ``threads`` unless the environment sets them: Dr.Jit's
    workers (``ROUGHLIGHT_THREADS``) as many, and llvmpipe's (``LP_NUM_THREADS``) as many, but none at one thread,
    where llvmpipe rasterises in the job's own thread. A single worker thread of its own took 13% more CPU for the
    same sweeps, the same to the bit (a regular, a random-pyramid and a heightfield sweep of the default views)."""
    n = int(snakemake.threads)
    os.environ.setdefault("ROUGHLIGHT_THREADS", str(n))
    os.environ.setdefault("LP_NUM_THREADS", "0" if n == 1 else str(n))


def use(snakemake):
    """The job's OpenGL platform (``params.gl``) and its renderers' threads (:func:`threads`)."""
    threads(snakemake)
    gl = dict(snakemake.params.gl)
    os.environ["PYOPENGL_PLATFORM"] = str(gl["platform"])
    device = gl.get("egl_device")
    os.environ["ROUGHLIGHT_EGL_DEVICE"] = "" if device is None else str(int(device))
