# neghip (corpus/volumes/neghip.nhdr, 8-bit): the low-probability cloud faint
# blue, the lobes orange, the cores white.
0        0    0    0    0
30       0.2  0.6  1    0
60       0.2  0.6  1    0.03
150      1    0.4  0.2  0.4
255      1    1    1    0.8
