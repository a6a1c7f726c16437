# A translucent ramp for analytic fields (values about [0, 1]), coloured so that
# colour as well as opacity is compared (tests/volpack_test.cpp).
0    0.2 0.4 1.0 0
0.5  1.0 0.6 0.2 0.05
1    1.0 1.0 1.0 0.3
