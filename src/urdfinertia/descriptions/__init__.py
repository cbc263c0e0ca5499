"""Robot description documents: read them into one robot model, splice inertials back.

Owns the robot model (`.model`: frozen dataclasses with source lines), the format
registry (`.formats`: URDF today, each format a sibling subpackage that reads its
bytes into the model and splices new inertials into the same bytes), the one hardened XML
parsing path (`.xml`), mesh URI resolution (`.paths`: `package://`,
`file://`) and the joint tree (`.kinematics`). May import: `urdfinertia.inertia`,
the foundation modules (`errors`), numpy and lxml; never meshes, links or the CLI.
"""
