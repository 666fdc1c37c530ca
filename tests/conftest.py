"""The tests' root: pytest puts this folder on sys.path (the default "prepend" import mode,
no __init__.py), so every test module, in any subfolder, imports the shared small scenes as
``import scenes`` (tests/scenes.py)."""
