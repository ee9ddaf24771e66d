# tests for mesh (owned by the mesh module)
