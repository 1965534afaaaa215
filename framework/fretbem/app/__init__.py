"""The application layer: the command line and the public run pipeline."""
