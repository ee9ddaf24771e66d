# Sources of torus/ (closed genus-1 meshes onto a flat torus); included by the top-level CMakeLists.txt.
set(AU_TORUS_SOURCES
  torus/au_torus_homology.c
  torus/au_torus_init.c
)
