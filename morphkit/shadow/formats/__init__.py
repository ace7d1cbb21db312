"""The shadow atlas file: :mod:`.atlasfile` (one versioned ``.npz``, checked on load)."""
