"""A seeded mutation fuzzer of ``urdf-inertia check`` and ``fix``, shared by the test suite
(``tests/test_fuzz.py``, a short slice) and ``scripts/fuzz.py`` (a long run).

- :mod:`.seeds`: the real files mutated (example-robot-data URDF, xacro and SDFormat; the
  drake wheel's SDFormat models; dm_control and robosuite MJCF; the repository's USD test
  assets; real STL, OBJ and COLLADA meshes, and PLY/GLB/ASCII STL made from them);
- :mod:`.mutate` (descriptions) and :mod:`.meshes` (mesh files): the mutators, each a pure
  function of the bytes and a seeded ``random.Random``;
- :mod:`.cases`: a case is a seed, the mutations applied and the file-system objects
  (FIFOs, folders, sparse files, symbolic-link loops) the mutant refers to; one seed of
  the generator gives the same cases on every machine with the same collections;
- :mod:`.runner`: runs each command of a case in a forked child of a process that has
  imported the package once, under a wall-clock timeout and an address-space limit;
- :mod:`.classify`: what a run did (:data:`~.classify.CLASSES`), reading the output back
  and testing every inertial with :mod:`urdfinertia.inertia.validity`;
- :mod:`.table`: the figures per class and per format.

Nothing here touches the network: every mutant and every file it names is made under a
temporary folder, and the seeds are read, never written.
"""
