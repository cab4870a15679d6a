"""Reading what superdex::WriteVtu and superdex::VtkSeries write (ASCII .vtu
frames and their .pvd list), for the examples' plot scripts.

Import it from a script beside ../common:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
    from vtu import read_pvd, read_vtu, VTK_TETRA
"""
import os
import xml.etree.ElementTree as ET

import numpy as np

VTK_POLY_LINE = 4
VTK_TRIANGLE = 5
VTK_TETRA = 10
_NODES = {VTK_TRIANGLE: 3, VTK_TETRA: 4}

# the 4 faces of a tetrahedron, as node positions within it
TET_FACES = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))


def read_pvd(path):
    """[(time, absolute .vtu path)] in file order."""
    root = ET.parse(path).getroot()
    folder = os.path.dirname(path)
    return [
        (float(d.get("timestep")), os.path.join(folder, d.get("file")))
        for d in root.iter("DataSet")
    ]


def _read_piece(path):
    """points (n×3), the cells as (start, end, type) index ranges into the
    connectivity, the connectivity and the point arrays (name → n×k)."""
    piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")

    def values(array, dtype=float):
        return np.array(array.text.split(), dtype=dtype)

    points = values(piece.find("Points/DataArray")).reshape(-1, 3)
    cells = {a.get("Name"): a for a in piece.find("Cells")}
    connectivity = values(cells["connectivity"], int)
    offsets = values(cells["offsets"], int)
    types = values(cells["types"], int)
    starts = np.concatenate([[0], offsets[:-1]])
    data = {}
    point_data = piece.find("PointData")
    for array in [] if point_data is None else point_data:
        k = int(array.get("NumberOfComponents", "1"))
        data[array.get("Name")] = values(array).reshape(-1, k).squeeze()
    return points, list(zip(starts, offsets, types)), connectivity, data


def read_vtu(path, cell_type):
    """points (n×3), the cells of `cell_type` (m×nodes) and the point arrays
    (name → n×k) of an ASCII .vtu."""
    points, cells, connectivity, data = _read_piece(path)
    n = _NODES[cell_type]
    kept = np.array([connectivity[s:s + n] for s, _, t in cells if t == cell_type], dtype=int)
    return points, kept.reshape(-1, n), data


def read_polylines(path):
    """points (n×3), the polylines (a list of index arrays) and the point
    arrays (name → n×k) of an ASCII .vtu of polylines (WriteRodsVtu)."""
    points, cells, connectivity, data = _read_piece(path)
    lines = [connectivity[s:e] for s, e, t in cells if t == VTK_POLY_LINE]
    return points, lines, data


def front_faces(tets, reference):
    """The tets' faces on the side z = max of the reference (undeformed) mesh."""
    zmax = reference[:, 2].max()
    on_front = reference[:, 2] > zmax - 1e-9 * (1 + abs(zmax))
    faces = []
    for tet in tets:
        for f in TET_FACES:
            face = tet[list(f)]
            if on_front[face].all():
                faces.append(face)
    return np.array(faces, dtype=int)
