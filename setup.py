"""The compiled part of designer: the comparison's kernels (designer/evaluate/csrc) and
the terrain's ray marching and noise (designer/core/csrc).

Everything else is configured in pyproject.toml. ``pip install -e .`` builds the
extension beside its sources; it needs a C compiler and the Python headers.
"""

from setuptools import Extension, setup

#: the buffer-protocol helpers both modules include
BUFFERS_H = "designer/csrc/buffers.h"

setup(
    ext_modules=[
        Extension(
            "designer.evaluate._ckernels",
            sources=[f"designer/evaluate/csrc/{name}.c"
                     for name in ("module", "bvh", "topology", "grid", "parallel")],
            depends=[f"designer/evaluate/csrc/{name}.h"
                     for name in ("kernels", "closest", "parallel")] + [BUFFERS_H],
            include_dirs=["designer/csrc"],
            # IEEE arithmetic as written: no fused multiply-adds, no fast-math
            extra_compile_args=["-O3", "-std=c11", "-ffp-contract=off", "-fno-math-errno",
                                "-Wall", "-Wextra", "-Wno-unused-parameter",
                                "-Wno-missing-field-initializers"],
            extra_link_args=["-pthread"],
        ),
        Extension(
            "designer.core._cterrain",
            sources=["designer/core/csrc/terrain.c"],
            depends=[BUFFERS_H],
            include_dirs=["designer/csrc"],
            extra_compile_args=["-O3", "-std=c11", "-ffp-contract=off", "-fno-math-errno",
                                "-Wall", "-Wextra", "-Wno-unused-parameter"],
        ),
    ],
)
