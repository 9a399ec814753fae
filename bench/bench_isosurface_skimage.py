"""Time scikit-image's marching_cubes on a .npy field for bench_isosurface.

usage: bench_isosurface_skimage.py FIELD.npy LEVEL REPEATS OUT_PREFIX
Times only the marching_cubes call (best of REPEATS), writes OUT_PREFIX.verts (float64,
V×3) and OUT_PREFIX.faces (int32, F×3) and prints one JSON line:
{"seconds": …, "vertices": …, "faces": …, "version": …}
"""
import json
import sys
import time

import numpy as np
import skimage
from skimage import measure


def main():
    path, level, repeats, out = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    volume = np.load(path)
    best = float("inf")
    verts = faces = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        verts, faces, _normals, _values = measure.marching_cubes(volume, level=level)
        best = min(best, time.perf_counter() - t0)
    np.ascontiguousarray(verts, dtype=np.float64).tofile(out + ".verts")
    np.ascontiguousarray(faces, dtype=np.int32).tofile(out + ".faces")
    print(json.dumps({"seconds": best, "vertices": int(len(verts)), "faces": int(len(faces)),
                      "version": skimage.__version__}))


if __name__ == "__main__":
    main()
