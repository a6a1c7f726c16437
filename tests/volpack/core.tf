# For analytic fields whose values grow towards the box (sphere, torus): the
# low values inside opaque-ish, transparent from 0.9 up, so that the box's
# faces, where VolPack's one-voxel apron and the reference's clipping differ
# most, stay empty (tests/volpack_test.cpp).
0    1.0 1.0 0.9 0.25
0.3  1.0 0.5 0.2 0.1
0.6  0.2 0.5 1.0 0.03
0.9  0.2 0.5 1.0 0
