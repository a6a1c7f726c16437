# neghip (8-bit, 0..255): the low-density cloud faint and blue, the cores opaque
# and warm (tests/volpack_test.cpp).
20   0.2 0.3 1.0 0
60   0.3 0.9 0.4 0.08
120  1.0 0.8 0.3 0.4
255  1.0 1.0 1.0 0.8
