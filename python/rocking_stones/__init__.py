"""rocking_stones: micro- and macro-equilibria of pebbles and rocking stones.

The Python face of the Rust library ``rocking_stones`` (the ``rocking`` command line tool): the
same analysis, on a mesh file, a ``(vertices, faces)`` pair of numpy arrays or a
``trimesh.Trimesh``.

>>> import rocking_stones as rs
>>> a = rs.analyze(rs.generate("cube"))
>>> a.micro, a.macro
((6, 8, 12), (6, 8, 12))

Every number is computed by the Rust library; ``to_dict()`` is the very value
``rocking analyze --json`` prints. Long runs (``drop``, ``perturb``, ``shake``, ``study``)
release the GIL and stop on Ctrl-C; they use ``RAYON_NUM_THREADS`` threads (default: all cores)
or ``threads=`` for one call.
"""

from ._native import (
    DEFAULT_COPLANAR_TOL,
    PAPER_NU,
    Analysis,
    Basins,
    DropResult,
    DynamicsResult,
    MeshError,
    Study,
    __version__,
    analyze,
    basins,
    drop,
    generate,
    num_threads,
    perturb,
    shake,
    shake_rock,
    study,
)

__all__ = [
    "DEFAULT_COPLANAR_TOL",
    "PAPER_NU",
    "Analysis",
    "Basins",
    "DropResult",
    "DynamicsResult",
    "MeshError",
    "Study",
    "__version__",
    "analyze",
    "basins",
    "drop",
    "generate",
    "num_threads",
    "perturb",
    "shake",
    "shake_rock",
    "study",
]
