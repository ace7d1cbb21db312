"""A user's scene, written down: the assets, their instances, the camera, the sun, the ground.

A scene is data (what a file says), read from and written to files here, and drawn by the
programs (``morphkit render SCENE``). Two kinds of file describe one:

* a JSON scene file (versioned, checked against the JSON Schema shipped with morphkit) naming
  asset files, listed or scattered instances, a camera path, a sun and the image size;
* a glTF scene (``.glb``/``.gltf``): each mesh an asset, the nodes that use it its instances,
  its directional light the sun and its camera the camera, in the file's own units.

The scene's assets are baked (or read) by the programs, not here: reading a scene file does no
rendering.
"""
