"""mesh.repair."""
