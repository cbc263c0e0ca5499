"""descriptions.urdf."""
