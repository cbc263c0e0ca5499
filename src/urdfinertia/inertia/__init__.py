"""inertia."""
