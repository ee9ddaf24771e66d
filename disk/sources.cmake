# Sources of disk/ (disk, annulus and square maps); included by the top-level CMakeLists.txt.
set(AU_DISK_SOURCES
  disk/au_disk_init.c
  disk/au_disk_square.c
  disk/au_disk_map.c
  disk/au_circles.c
)
