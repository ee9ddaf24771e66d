# Sources of disk/ (disk, annulus and square maps); included by the top-level CMakeLists.txt.
set(AU_DISK_SOURCES)
