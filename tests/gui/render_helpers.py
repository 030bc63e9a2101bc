"""Helpers of the Render panel tests: a stand-in render process."""

from __future__ import annotations

import textwrap

FAKE_RENDER = textwrap.dedent("""
    import json, signal, sys, time
    from pathlib import Path
    import numpy as np, cv2
    out, n, delay = Path(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
    (out / "images").mkdir(parents=True, exist_ok=True)
    def stop(*_):
        print("interrupted", file=sys.stderr, flush=True)
        sys.exit(130)
    signal.signal(signal.SIGINT, stop)
    print(json.dumps({"event": "worker_started", "worker": 0, "pid": 1,
                      "frames": list(range(n))}), flush=True)
    print(json.dumps({"event": "scene_ready", "seconds": 0.1}), flush=True)
    for i in range(n):
        time.sleep(delay)
        path = out / "images" / f"IMG_{i + 1:05d}.png"
        image = np.zeros((60, 90, 3), np.uint8)
        image[:, : 10 * (i + 1)] = (0, 200, 0)
        cv2.imwrite(str(path), image)
        print(json.dumps({"event": "frame_done", "index": i, "path": str(path),
                          "seconds": delay}), flush=True)
    print(json.dumps({"event": "worker_done"}), flush=True)
""")
