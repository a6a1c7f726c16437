# The buckyball's electron density (corpus/volumes/bucky.nhdr, 8-bit): the
# carbon shells faint blue, the atoms' cores orange to white.
# value  r    g    b    alpha (per voxel of depth)
0        0    0    0    0
60       0.3  0.5  1    0
100      0.3  0.5  1    0.05
160      1    0.7  0.3  0.5
255      1    1    1    0.9
