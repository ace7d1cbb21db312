"""The programs: what the ``morphkit`` command runs, above the library.

The library (the core, the two wings, :mod:`morphkit.sunlit`, :mod:`morphkit.bake`) is used
through its Python API; these modules turn it into commands that write files:

* :mod:`.cliargs`, :mod:`.clistop` -- the command line's shared arguments, and how a run
  stops (Ctrl-C, SIGTERM) leaving its folder as it was;
* :mod:`.demo` -- ``morphkit demo``: the demo scenes into a folder;
* :mod:`.playback` -- ``morphkit shadows``: a baked shadow atlas's scene along an object path;
* :mod:`.scenerender` -- ``morphkit render SCENE`` and ``morphkit billboards``: a scene drawn into
  a folder (``billboards`` is the scene its flags describe);
* :mod:`.village` -- the example glTF village (``samples/scenes/village.glb``);
* :mod:`.sequence` -- a billboard scene along a camera path: frames, a video, strips;
* :mod:`.sources` -- where a command's billboard assets come from (names, mesh or asset files);
* :mod:`.video` -- the video writer (a temporary renamed into place when finished);
* :mod:`.visualize` -- side-by-side images of the demo;
* :mod:`.fixtures` -- the demo's scenes, shared with the benchmarks (nothing in the library
  imports them).

The command line itself is :mod:`morphkit.cli`.
"""
