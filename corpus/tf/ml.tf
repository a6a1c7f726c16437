# Marschner-Lobb (values in [0, 1]; the classic surface at 0.5): a shell around
# 0.5, the inside warmer.
0.3      0.2  0.4  1    0
0.5      0.2  0.4  1    0.1
0.8      1    0.6  0.2  0.6
1        1    1    1    0.6
