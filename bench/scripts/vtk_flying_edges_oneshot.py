#!/usr/bin/python3
"""One vtkFlyingEdges3D call as a user of VTK's Python makes it (issue #35).

    /usr/bin/python3 vtk_flying_edges_oneshot.py VOLUME.nrrd ISO THREADS [REPEAT]

Reads a raw little-endian float NRRD (the header's sizes; numpy), wraps it as
vtkImageData (no copy), then runs a fresh vtkFlyingEdges3D's Update() REPEAT
times (default 1), each on a new filter once the one before is released, and
prints one line per Update, parseable like lockstep's stats line:

    vtkFlyingEdges3D: 2521956 triangles, update 0.412 s (72200 page faults, system 0.570 s)

The first Update is VTK's one-shot figure (its memory fresh), the last its
warm one. The process's environment decides the memory VTK gets (e.g.
GLIBC_TUNABLES=glibc.malloc.hugetlb=1: glibc's transparent huge pages).
"""
import re
import resource
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support


def read_nrrd(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"\n\n") + 2
    header = data[:end].decode()
    sizes = [int(x) for x in re.search(r"sizes: *(\d+) +(\d+) +(\d+)", header).groups()]
    if "type: float" not in header or "encoding: raw" not in header:
        sys.exit(f"{path}: only raw float NRRDs are read here")
    return sizes, np.frombuffer(data, dtype="<f4", offset=end, count=sizes[0] * sizes[1] * sizes[2])


def main():
    path, iso, threads = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
    repeat = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    sizes, samples = read_nrrd(path)
    vtk.vtkSMPTools.Initialize(threads)
    image = vtk.vtkImageData()
    image.SetDimensions(*sizes)
    array = numpy_support.numpy_to_vtk(samples, deep=False)
    image.GetPointData().SetScalars(array)
    for _ in range(repeat):
        fe = vtk.vtkFlyingEdges3D()
        fe.SetInputData(image)
        fe.SetValue(0, iso)
        fe.ComputeNormalsOff()
        fe.ComputeGradientsOff()
        fe.ComputeScalarsOff()
        before = resource.getrusage(resource.RUSAGE_SELF)
        t0 = time.perf_counter()
        fe.Update()
        seconds = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_SELF)
        triangles = fe.GetOutput().GetNumberOfPolys()
        print(f"vtkFlyingEdges3D: {triangles} triangles, update {seconds:.4f} s "
              f"({after.ru_minflt - before.ru_minflt} page faults, system {after.ru_stime - before.ru_stime:.3f} s)",
              flush=True)
        del fe


if __name__ == "__main__":
    main()
