"""Robot description documents: read them into one robot model, splice inertials back.

Owns the robot model (:mod:`.model`: frozen dataclasses with source lines), the format
registry (:mod:`.formats`: URDF today, each format a sibling subpackage that reads its
bytes into the model and splices new inertials into the same bytes), the one hardened XML
parsing path (:mod:`.xml`), mesh URI resolution (:mod:`.paths`: ``package://``,
``file://``) and the joint tree (:mod:`.kinematics`). May import: :mod:`urdfinertia.inertia`,
the foundation modules (``errors``), numpy and lxml; never meshes, links or the CLI.
"""
