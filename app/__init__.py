"""The texeditor desktop application (PySide6 + pyqtgraph) on top of the `texeditor` engine.

The engine never imports this package; widgets here turn user input into Actions and show documents.
"""
