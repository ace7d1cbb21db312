"""The parts of ``morphkit bench scene`` (:mod:`morphkit.bench.scene_suite`): the field, its methods
and truth (:mod:`.fields`), the point levels (:mod:`.levels`) and the receivers' resolution
(:mod:`.resolution`)."""
