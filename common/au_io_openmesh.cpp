// au_io_openmesh.cpp - (being written)
