# A soft, opaque sphere for corpus/volumes/sphere-32.field (f = |p|, 0 at the centre):
# alpha per voxel 0.4 inside |p| = 0.3, falling linearly to 0 at |p| = 1; colour
# white at the centre to blue outside. Smooth, so a fine step is accurate, and
# opaque, so most rays through it stop early: at 64x64, view 30,20, step 1/8
# without termination is 3.9e-6 per channel from step 1/16 over the covered
# pixels, and early termination at eps 1/256 adds 5.5e-4 (tests/volume_error_test.cpp,
# ctest volume.error_chooses_eps, bad_volume_view.error_cannot_be_met).
# value r g b alpha
0    1   1   1   0.4
0.3  1   0.8 0.5 0.4
1.0  0.3 0.5 1   0
