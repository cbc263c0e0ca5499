"""mesh.read."""
