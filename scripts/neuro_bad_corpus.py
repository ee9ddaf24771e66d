#!/usr/bin/python3
"""neuro_bad_corpus.py - write the FreeSurfer and GIfTI files of the bad-input corpus (tests/cli/bad/).

Each file is a small tetrahedron made wrong in one way (issue 19: truncated and lying files); the
GIfTI files are written as giftiio writes them (base64 of zlib data, little-endian). Run from the
repository's root: /usr/bin/python3 scripts/neuro_bad_corpus.py (needs only the standard library).
"""
import base64, gzip, struct, zlib

D = "tests/cli/bad/"
V = [(0., 0., 0.), (1., 0., 0.), (0., 1., 0.), (0., 0., 1.)]
F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def fs_surface(nv=4, faces=F, stamp=b"created by neuro_bad_corpus.py on Wed Dec  2 2026\n\n", magic=b"\xff\xff\xfe"):
    b = magic + stamp + struct.pack(">ii", nv, len(faces))
    b += b"".join(struct.pack(">fff", *v) for v in V)
    return b + b"".join(struct.pack(">iii", *f) for f in faces)


def da(intent, dtype, rows, cols, data, fmt, dim0=None, extra=""):
    raw = b"".join(struct.pack("<" + fmt * len(r), *r) for r in data)
    enc = base64.b64encode(zlib.compress(raw)).decode()
    dims = ('Dimensionality="2" Dim0="%d" Dim1="%d"' % (dim0 or rows, cols) if cols > 1 else
            'Dimensionality="1" Dim0="%d"' % (dim0 or rows))
    return ('<DataArray Intent="%s" DataType="%s" ArrayIndexingOrder="RowMajorOrder" %s Encoding="GZipBase64Binary" '
            'Endian="LittleEndian" ExternalFileName="" ExternalFileOffset=""%s>\n<Data>%s</Data>\n</DataArray>\n'
            % (intent, dtype, dims, extra, enc))


def gifti(*arrays):
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<GIFTI Version="1.0" NumberOfDataArrays="%d">\n%s</GIFTI>\n'
            % (len(arrays), "".join(arrays))).encode()


def pts(**kw):
    return da("NIFTI_INTENT_POINTSET", "NIFTI_TYPE_FLOAT32", 4, 3, V, "f", **kw)


def tri(faces=F, **kw):
    return da("NIFTI_INTENT_TRIANGLE", "NIFTI_TYPE_INT32", len(faces), 3, faces, "i", **kw)


def put(name, data):
    open(D + name, "wb").write(data)


good = fs_surface()
put("truncated.white", good[:-10])                        # the faces cut short
put("lying_count.white", fs_surface(nv=1000000))          # announces a million vertices
put("index_range.white", fs_surface(faces=F[:3] + [(1, 2, 7)]))
put("no_stamp.white", b"\xff\xff\xfe" + good[good.index(b"\n\n") + 2:])  # counts right after the magic
put("quad.white", fs_surface(magic=b"\xff\xff\xff"))      # a curv file's (or quad surface's) magic
ok = gifti(pts(), tri())
put("truncated.gii", ok[:len(ok) * 2 // 3])
put("truncated.gii.gz", gzip.compress(ok, mtime=0)[:-12])
put("lying_dims.gii", gifti(pts(dim0=2000000000), tri()))  # more values than a file of its size holds
put("short_data.gii", gifti(pts(dim0=40), tri()))          # Dim0 40, data for 4 vertices
put("corrupt_data.gii", ok.replace(b"<Data>", b"<Data>!!!!", 1))
put("no_triangles.gii", gifti(pts()))
put("values.shape.gii", gifti(da("NIFTI_INTENT_SHAPE", "NIFTI_TYPE_FLOAT32", 4, 1, [(1,), (2,), (3,), (4,)], "f")))
put("index_range.gii", gifti(pts(), tri(F[:3] + [(1, 2, 9)])))
put("external.gii", gifti(pts().replace('ExternalFileName=""', 'ExternalFileName="/dev/zero"'), tri()))
put("short_ascii.gii", gifti(('<DataArray Intent="NIFTI_INTENT_POINTSET" DataType="NIFTI_TYPE_FLOAT32" '
    'ArrayIndexingOrder="RowMajorOrder" Dimensionality="2" Dim0="4" Dim1="3" Encoding="ASCII" Endian="LittleEndian" '
    'ExternalFileName="" ExternalFileOffset="">\n<Data>0 0 0 1 0 0 0 1 0 0 0</Data>\n</DataArray>\n'), tri()))
put("mismatched_tag.gii", ok.replace(b"<DataArray", b"<DataArraw", 1))  # giftiio itself crashes on it
put("misplaced.gii", ok.replace(b"<DataArray", b"<Data>0</Data>\n<DataArray", 1))
