// au_io_openmesh.cpp - the OpenMesh bridge: reads a mesh file into plain arrays behind an extern "C" API.
#include "au_io_internal.h"

// GCC 12 warns inside OpenMesh's own templates (its vectors are deliberately left uninitialized
// by their default constructor); the warning is about OpenMesh, not this file.
// (clang has no such warning and would warn about the unknown option instead.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <climits>
#include <cstdlib>
#include <exception>
#include <new>

namespace {

// Double positions, so that nothing is rounded on our side of the reader.
struct au_om_traits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<au_om_traits> au_om_mesh;

// A polygon mesh is used instead of a triangle mesh so that quads reach us as quads (and are
// rejected by name) rather than being triangulated behind the user's back.
au_status read_arrays(const char *path, int *nv, int *nf, double **X, int **F, au_msg *msg) {
  // The library never prints; OpenMesh's diagnostics would go to stderr, so they are switched off.
  omerr().disable();
  omlog().disable();
  omout().disable();
  au_om_mesh mesh;
  OpenMesh::IO::Options opts;
  if (!OpenMesh::IO::read_mesh(mesh, path, opts))
    return au_msg_set(msg, AU_E_FORMAT, "%s: OpenMesh could not read the file (malformed or truncated)", path);
  if (mesh.n_vertices() > (size_t)(INT_MAX / 3) || mesh.n_faces() > (size_t)(INT_MAX / 3))
    return au_msg_set(msg, AU_E_FORMAT, "%s: too many vertices or faces", path);
  const int n_v = (int)mesh.n_vertices(), n_f = (int)mesh.n_faces();
  for (au_om_mesh::FaceHandle fh : mesh.faces()) {
    if (mesh.valence(fh) != 3)
      return au_msg_set(msg, AU_E_FACE, "%s: face %d has %u corners; only triangles are supported", path,
                        fh.idx(), mesh.valence(fh));
  }
  double *x = static_cast<double *>(std::malloc(sizeof(double) * 3 * (size_t)(n_v > 0 ? n_v : 1)));
  int *f = static_cast<int *>(std::malloc(sizeof(int) * 3 * (size_t)(n_f > 0 ? n_f : 1)));
  if (!x || !f) {
    std::free(x);
    std::free(f);
    return au_msg_set(msg, AU_E_NOMEM, "%s: out of memory", path);
  }
  for (au_om_mesh::VertexHandle vh : mesh.vertices()) {
    const au_om_mesh::Point &p = mesh.point(vh);
    for (int k = 0; k < 3; k++) x[3 * vh.idx() + k] = p[k];
  }
  // The face's first corner is the first index given to add_face, so corners keep the file's order.
  for (au_om_mesh::FaceHandle fh : mesh.faces()) {
    int k = 0;
    for (au_om_mesh::VertexHandle vh : mesh.fv_range(fh)) f[3 * fh.idx() + k++] = vh.idx();
  }
  *nv = n_v;
  *nf = n_f;
  *X = x;
  *F = f;
  return AU_OK;
}

}  // namespace

extern "C" au_status au_io__openmesh_read(const char *path, int *nv, int *nf, double **X, int **F, au_msg *msg) {
  if (!path || !nv || !nf || !X || !F) return au_msg_set(msg, AU_E_ARG, "au_io__openmesh_read: NULL argument");
  *X = NULL;
  *F = NULL;
  *nv = *nf = 0;
  try {
    return read_arrays(path, nv, nf, X, F, msg);
  } catch (const std::bad_alloc &) {
    return au_msg_set(msg, AU_E_NOMEM, "%s: out of memory in the OpenMesh reader", path);
  } catch (const std::exception &e) {
    return au_msg_set(msg, AU_E_INTERNAL, "%s: OpenMesh failed: %s", path, e.what());
  } catch (...) {
    return au_msg_set(msg, AU_E_INTERNAL, "%s: OpenMesh failed with an unknown exception", path);
  }
}
