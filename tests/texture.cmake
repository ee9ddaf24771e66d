# tests for the spherical textures and sampling (sphere/ texture module)
