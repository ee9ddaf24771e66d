#!/usr/bin/env python3
"""midpoint_subdivide.py IN OUT.obj -- split every triangle of IN (.obj or .off) into four at its
edge midpoints. The surface stays exactly the same; edges halve. Used to measure how the chord
(Schwarz lantern) error of a sphere map falls with resolution (docs/sphere.md)."""
import sys


def load(path):
    V, F = [], []
    if path.endswith('.off'):
        t = open(path).read().split()
        i = 1 if t[0] == 'OFF' else 0
        nv, nf = int(t[i]), int(t[i + 1])
        i += 3
        V = [tuple(float(x) for x in t[i + 3 * k:i + 3 * k + 3]) for k in range(nv)]
        i += 3 * nv
        for _ in range(nf):
            n = int(t[i])
            F.append(tuple(int(x) for x in t[i + 1:i + 1 + n]))
            i += 1 + n
        return V, F
    for line in open(path):
        s = line.split()
        if s and s[0] == 'v':
            V.append(tuple(float(x) for x in s[1:4]))
        elif s and s[0] == 'f':
            F.append(tuple(int(x.split('/')[0]) - 1 for x in s[1:]))
    return V, F


def main():
    V, F = load(sys.argv[1])
    mid = {}

    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            mid[k] = len(V)
            V.append(tuple((V[a][i] + V[b][i]) / 2 for i in range(3)))
        return mid[k]

    out = []
    for a, b, c in F:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    with open(sys.argv[2], 'w') as f:
        for v in V:
            f.write('v %.17g %.17g %.17g\n' % v)
        for t in out:
            f.write('f %d %d %d\n' % (t[0] + 1, t[1] + 1, t[2] + 1))


if __name__ == '__main__':
    main()
