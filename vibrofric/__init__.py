"""vibrofric: friction and drive force of a body sliding over an in-plane vibrating base."""

__version__ = "0.1.0"
