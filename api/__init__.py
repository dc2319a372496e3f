"""The HTTP service and the ``engram`` command line: the outermost layer."""
