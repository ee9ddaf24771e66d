# tests for sphere (owned by the sphere module)
