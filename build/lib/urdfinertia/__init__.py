"""urdfinertia: correct the <inertial> tags of URDF robot descriptions from their geometry."""

__version__ = "0.1.0"
