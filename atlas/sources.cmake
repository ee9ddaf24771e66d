# Sources of atlas/ (surfaces of any genus: the flat cone metric that starts an atlas); included by the
# top-level CMakeLists.txt.
set(AU_ATLAS_SOURCES
  atlas/au_atlas_flow.c
  atlas/au_atlas_holonomy.c
  atlas/au_atlas_layout.c
  atlas/au_atlas_metric.c
)
