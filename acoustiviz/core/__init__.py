"""The physics core: medium, materials, Hertz contact, rigid-sphere radiation and image sources.

It also holds the near- and far-field approximations. It knows nothing of grids, plots or files,
and writes none.
"""
