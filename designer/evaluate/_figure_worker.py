"""Helper process of :class:`designer.evaluate.figures.FigureWriter`.

Imports matplotlib and rasterio at once, then runs the pickled jobs it reads from
standard input — ``(name, args, kwargs)`` calls of a writer in :mod:`.maps` — until
end of input. Exit code 0 when every job succeeded; otherwise the error is the last
line of standard error and the exit code is 1.
"""

from __future__ import annotations

import pickle
import sys


def main() -> int:
    from matplotlib.backends import backend_agg  # noqa: F401  (imported while waiting)
    from matplotlib.figure import Figure  # noqa: F401

    from designer.evaluate import maps
    from designer.evaluate.figures import JOBS

    try:
        import rasterio  # noqa: F401
    except ImportError:
        pass  # reported by the GeoTIFF job, if one comes
    stdin = sys.stdin.buffer
    while True:
        try:
            name, args, kwargs = pickle.load(stdin)
        except EOFError:
            return 0
        if name not in JOBS:
            raise ValueError(f"unknown figure job {name!r}")
        getattr(maps, name)(*args, **kwargs)


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:  # Ctrl-C reaches the whole process group: stop quietly
        sys.exit(130)
    except Exception as exc:  # one line for the parent's error message
        detail = str(exc).splitlines()[0] if str(exc) else ""
        print(f"{type(exc).__name__}: {detail}", file=sys.stderr)
        sys.exit(1)
