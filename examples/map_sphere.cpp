// map_sphere.cpp - the same program from C++: the header is extern "C", the results are plain
// arrays, and a std::unique_ptr with the library's free function owns each of them.
// Build: c++ map_sphere.cpp $(pkg-config --cflags --libs authalic) -o map_sphere_cpp
#include <authalic.h>

#include <cstdio>
#include <memory>

struct mesh_deleter {
  void operator()(au_mesh *m) const { au_mesh_free(&m); }
};
struct result_deleter {
  void operator()(au_result *r) const { au_result_free(&r); }
};

int main(int argc, char **argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: map_sphere_cpp IN OUT\n");
    return 2;
  }
  au_msg msg = {{0}};
  au_mesh *raw_mesh = nullptr;
  au_status st = au_mesh_read(argv[1], &raw_mesh, &msg);
  std::unique_ptr<au_mesh, mesh_deleter> mesh(raw_mesh);
  std::unique_ptr<au_result, result_deleter> result;
  if (st >= 0) {
    au_options o = au_options_default();
    au_result *raw = nullptr;
    st = au_map(mesh->X, mesh->nv, mesh->F, mesh->nf, AU_TARGET_SPHERE, &o, &raw, &msg);
    result.reset(raw);
  }
  if (st >= 0) st = au_mesh_write(argv[2], result->nv, result->P, result->nf, result->F, nullptr, &msg);
  if (st < 0) {
    std::fprintf(stderr, "map_sphere_cpp: %s: %s\n", au_status_str(st), msg.text);
    return au_status_is_input_error(st) ? 2 : 1;
  }
  std::printf("V=%d F=%d steps=%d folds=%d mean|r-1|=%.4f vertex|log r|=%.5f\n", result->nv, result->nf,
              result->conv.steps, result->metrics.folds, result->metrics.r_mean_abs_dev,
              result->metrics.vertex_logr_mean_abs);
  return 0;
}
