"""vtkvec.py: the point vectors of an ASCII legacy VTK step file (keratome-vtk(5)), for the
tests' own checks; a second reader beside curvature's and meshio's.

point_vectors(path) -> {name: [(x, y, z), ...]}: every VECTORS block of the POINT_DATA section,
one 3-tuple per point; CELL_DATA vectors are skipped."""


def point_vectors(path):
    lines = open(path).read().split("\n")
    out, npts, i = {}, 0, 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("POINT_DATA"):
            npts = int(line.split()[1])
        elif line.startswith("CELL_DATA"):
            npts = 0
        elif line.startswith("VECTORS") and npts:
            v = [float(x) for x in " ".join(lines[i + 1:i + 1 + npts]).split()]
            if len(v) != 3 * npts:
                raise ValueError(f"{path}:{i + 1}: expected {3 * npts} numbers in {line.split()[1]}, found {len(v)}")
            out[line.split()[1]] = [tuple(v[3 * k:3 * k + 3]) for k in range(npts)]
            i += npts
        i += 1
    return out


def flat(path, name="displacement"):
    """The point vector field NAME as one flat list x0, y0, z0, x1, ...; [] when the file has none."""
    return [c for t in point_vectors(path).get(name, []) for c in t]
