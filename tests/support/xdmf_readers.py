"""Opens a results.xdmf as ParaView's three XDMF readers and meshio read it, every frame, and
prints one line per reader for tests/xdmf_readers_test.cpp:

    pvbatch tests/support/xdmf_readers.py paraview out/results.xdmf
    /usr/bin/python3 tests/support/xdmf_readers.py meshio out/results.xdmf

    reader=legacy frames=5 points=940 arrays=body:1,displacement:3,... max_displacement=0.0123
      last_time=0.1 position_mismatch=0 material_sum=80

max_displacement and material_sum are of the last frame. position_mismatch is the largest
|x(frame) - x(frame 0) - displacement(frame)| over every frame and particle: zero when each
frame's geometry and attributes come from the same saved frame. (meshio keeps one geometry,
the first frame's, so there it is the largest displacement of frame 0.)
"""
import sys

import numpy as np


def summary(reader, times, points, arrays, last, mismatch):
    print("reader=%s frames=%d points=%d arrays=%s max_displacement=%.12g last_time=%.12g "
          "position_mismatch=%.3g material_sum=%d" % (
              reader, len(times), points, ",".join("%s:%d" % a for a in sorted(arrays)),
              float(np.linalg.norm(last["displacement"], axis=1).max()), times[-1], mismatch,
              int(last["material"].sum())))
    sys.stdout.flush()


def paraview(path):
    from paraview import servermanager
    from paraview.simple import XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT
    from vtkmodules.util.numpy_support import vtk_to_numpy

    readers = (("legacy", lambda: XDMFReader(FileNames=[path])),
               ("xdmf3_s", lambda: Xdmf3ReaderS(FileName=[path])),
               ("xdmf3_t", lambda: Xdmf3ReaderT(FileName=[path])))
    for name, make in readers:
        reader = make()
        reader.UpdatePipelineInformation()
        times = list(reader.TimestepValues)
        first, values, arrays, mismatch = None, {}, set(), 0.0
        for t in times:
            reader.UpdatePipeline(t)
            grid = servermanager.Fetch(reader)
            while grid.IsA("vtkMultiBlockDataSet"):
                grid = grid.GetBlock(0)
            data = grid.GetPointData()
            values = {}
            for k in range(data.GetNumberOfArrays()):
                array = data.GetArray(k)
                values[data.GetArrayName(k)] = vtk_to_numpy(array)
                arrays.add((data.GetArrayName(k), array.GetNumberOfComponents()))
            x = vtk_to_numpy(grid.GetPoints().GetData())[:, :2]
            first = x if first is None else first
            mismatch = max(mismatch, float(np.abs(x - first - values["displacement"][:, :2]).max()))
        summary(name, times, grid.GetNumberOfPoints(), arrays, values, mismatch)


def meshio_reader(path):
    import meshio

    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        times, arrays = [], set()
        for k in range(reader.num_steps):
            t, values, _ = reader.read_data(k)
            times.append(t)
            arrays |= {(n, 1 if a.ndim == 1 else a.shape[1]) for n, a in values.items()}
            if k == 0:  # meshio keeps one geometry, frame 0's: its displacement must be zero
                mismatch = float(np.abs(values["displacement"]).max())
    assert cells[0].type == "vertex" and len(cells[0].data) == len(points)
    summary("meshio", times, len(points), arrays, values, mismatch)


if __name__ == "__main__":
    {"paraview": paraview, "meshio": meshio_reader}[sys.argv[1]](sys.argv[2])
