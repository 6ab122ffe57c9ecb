"""The OpenGL platform of a rendering job, set before anything loads OpenGL.

``render.platform`` (``osmesa`` or ``egl``) and ``render.egl_device`` reach the job through the rule's
``params.gl`` (so a changed platform reruns what it renders); they win over whatever the environment says.
"""
import os


def use(snakemake):
    gl = dict(snakemake.params.gl)
    os.environ["PYOPENGL_PLATFORM"] = str(gl["platform"])
    device = gl.get("egl_device")
    os.environ["ROUGHLIGHT_EGL_DEVICE"] = "" if device is None else str(int(device))
