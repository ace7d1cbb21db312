"""The ``morphkit plan`` command: a scene planned to an error budget and verified.

:mod:`.planrun` plans and verifies, :mod:`.planverify` draws and measures the frames,
:mod:`.planreport` reports them, :mod:`.shadowplanrun` measures and chooses the frames' shadow.
"""
