# Sources and dependencies of the spherical textures in sphere/; included by the top-level CMakeLists.txt.
# GeographicLib (libgeographiclib-dev) supplies the projections behind the C++ bridge
# sphere/au_geographiclib.cpp; libpng (libpng-dev) writes and reads the pictures.
find_path(GEOGRAPHICLIB_INCLUDE_DIR GeographicLib/AlbersEqualArea.hpp REQUIRED)
find_library(GEOGRAPHICLIB_LIBRARY NAMES Geographic GeographicLib REQUIRED)
find_path(PNG_INCLUDE_DIR png.h REQUIRED)
find_library(PNG_LIBRARY NAMES png16 png REQUIRED)

set(AU_TEXTURE_SOURCES
  sphere/au_geographiclib.cpp
  sphere/au_locate.c
  sphere/au_texture.c
  sphere/au_texsplit.c
  sphere/au_octahedral.c
  sphere/au_image.c)
set(AU_TEXTURE_INCLUDE_DIRS ${GEOGRAPHICLIB_INCLUDE_DIR} ${PNG_INCLUDE_DIR})
set(AU_TEXTURE_LIBRARIES ${GEOGRAPHICLIB_LIBRARY} ${PNG_LIBRARY})

# The orientation predicates of au_locate.c rely on every product and sum being rounded separately.
set_source_files_properties(sphere/au_locate.c PROPERTIES COMPILE_OPTIONS "-ffp-contract=off")
