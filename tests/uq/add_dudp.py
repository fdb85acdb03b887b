#!/usr/bin/python3
"""add_dudp.py RUN_DIR NAME=KIND...: append POINT_DATA vectors dudp_NAME to every step VTK of a
run folder (legacy VTK, ASCII or big-endian BINARY as the file is), for the uncertainty-band tests
(tests/curvature_bands.sh, tests/uq_eye.sh). KIND says what the field is, per point:
  u        the point's displacement (so dR/dNAME = R(u) - R(0) for a reading linear in u)
  zero     0
  z        (0, 0, 1) mm: a rigid translation along the axis (every reading unchanged)
  rot      (-y, x, 0) of the deformed point: a rigid rotation about the axis, per radian
  uK       K times the displacement (K a number: uK2 = 2 u)
Reads the fields by a parser of its own (not keratome's)."""
import glob, os, re, struct, sys
import numpy as np

def parse(path):
    b = open(path, 'rb').read()
    binary = b.split(b'\n')[2].strip() == b'BINARY'
    pos = 0
    def line():
        nonlocal pos
        e = b.index(b'\n', pos)
        s = b[pos:e].decode(); pos = e + 1
        return s
    for _ in range(4): line()
    pts = disp = None; npts = 0; assoc = None
    while pos < len(b):
        s = line().strip()
        if not s: continue
        t = s.split()
        def values(count, typ):
            nonlocal pos
            if binary:
                size = {'double': 8, 'float': 4, 'int': 4}[typ]
                fmt = {'double': '>d', 'float': '>f', 'int': '>i'}[typ]
                a = np.frombuffer(b[pos:pos + size * count], dtype=fmt).astype(float)
                pos += size * count
                return a
            out = []
            while len(out) < count:
                out += line().split()
            return np.array(out[:count], dtype=float)
        if t[0] == 'POINTS':
            npts = int(t[1]); pts = values(3 * npts, t[2]).reshape(-1, 3)
        elif t[0] == 'CELLS':
            values(int(t[2]), 'int')
        elif t[0] == 'CELL_TYPES':
            values(int(t[1]), 'int')
        elif t[0] in ('POINT_DATA', 'CELL_DATA'):
            assoc = t[0]; n = int(t[1])
        elif t[0] == 'SCALARS':
            nc = int(t[3]) if len(t) > 3 else 1
            save = pos
            if line().strip().startswith('LOOKUP_TABLE') is False: pos = save
            values(n * nc, t[2])
        elif t[0] == 'VECTORS':
            a = values(3 * n, t[2]).reshape(-1, 3)
            if t[1] == 'displacement' and assoc == 'POINT_DATA': disp = a
        elif t[0] == 'FIELD':
            for _ in range(int(t[2])):
                h = line().split()
                values(int(h[1]) * int(h[2]), h[3])
        else:
            raise SystemExit(f'{path}: unexpected keyword {t[0]}')
    return binary, pts, disp

def main():
    run = sys.argv[1]
    kinds = [a.split('=', 1) for a in sys.argv[2:]]
    for path in sorted(glob.glob(os.path.join(run, 'step-*.vtk'))):
        binary, pts, u = parse(path)
        out = [b'\nPOINT_DATA %d\n' % len(pts)]
        for name, kind in kinds:
            if kind == 'u': v = u
            elif kind == 'zero': v = np.zeros_like(u)
            elif kind == 'z': v = np.tile([0.0, 0.0, 1.0], (len(u), 1))
            elif kind == 'rot':
                q = pts + u
                v = np.stack([-q[:, 1], q[:, 0], np.zeros(len(q))], axis=1)
            elif re.fullmatch(r'u[0-9.]+', kind): v = float(kind[1:]) * u
            else: raise SystemExit('unknown kind ' + kind)
            out.append(b'VECTORS dudp_%s double\n' % name.encode())
            if binary:
                out.append(np.asarray(v, dtype='>f8').tobytes() + b'\n')
            else:
                out.append(('\n'.join('%.17g %.17g %.17g' % tuple(r) for r in v) + '\n').encode())
        with open(path, 'ab') as f:
            f.write(b''.join(out))

main()
