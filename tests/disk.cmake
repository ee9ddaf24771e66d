# tests for disk/ (disk, annulus, square maps)
