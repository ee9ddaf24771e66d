# Sources and dependencies of the spherical textures in sphere/; included by the top-level CMakeLists.txt.
set(AU_TEXTURE_SOURCES)
set(AU_TEXTURE_INCLUDE_DIRS)
set(AU_TEXTURE_LIBRARIES)
