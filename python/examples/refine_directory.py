"""Refine every mesh of a directory on a Dask cluster: the path for collections that outgrow
one machine.

    python python/examples/refine_directory.py MESHES OUT --levels 2
    python python/examples/refine_directory.py MESHES OUT --scheduler tcp://host:8786

Each mesh is one task: a worker reads it, refines it with the scheme and options its file
sets, and writes `OUT/<name>.obj` (whole or not at all). subsurf runs each refinement on
the worker's own threads, so give workers one Dask thread and several cores each. Without
`--scheduler` a `LocalCluster` on this machine runs the tasks. Needs `dask.distributed`.
"""

import argparse
import os
from pathlib import Path

import subsurf

SUFFIXES = {".obj", ".ply", ".gltf", ".glb"}


def refine_file(src: str, dst: str, levels: int, scheme: str) -> dict:
    """Refines the mesh in `src` `levels` times and writes it to `dst`; returns what was
    done (plain data, so that it travels back from a worker)."""
    mesh = subsurf.read(src, scheme=scheme)
    refined = mesh.subdivide(levels)
    refined.write(dst)
    return {
        "input": src,
        "output": dst,
        "faces": mesh.num_faces,
        "refined_faces": refined.num_faces,
    }


def refine_directory(src_dir, out_dir, levels, client, scheme="catmullClark"):
    """Refines every mesh file of `src_dir` into `out_dir` on the Dask `client`; returns the
    results in file-name order, raising the first task's error if any failed."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = sorted(p for p in Path(src_dir).iterdir() if p.suffix.lower() in SUFFIXES)
    futures = [
        client.submit(refine_file, str(p), str(out / f"{p.stem}.obj"), levels, scheme, pure=False)
        for p in files
    ]
    return client.gather(futures)


def main():
    from dask.distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("src")
    parser.add_argument("out")
    parser.add_argument("--levels", type=int, default=2)
    parser.add_argument("--scheme", default="catmullClark")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler")
    args = parser.parse_args()
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=max(1, (os.cpu_count() or 2) // 2), threads_per_worker=1)
        client = Client(cluster)
    with client:
        for r in refine_directory(args.src, args.out, args.levels, client, args.scheme):
            print(f"{r['input']}: {r['faces']} -> {r['refined_faces']} faces, {r['output']}")


if __name__ == "__main__":
    main()
