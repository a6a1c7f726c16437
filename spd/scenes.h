// lockstep spd: the generators, one per SPD program (spd/<name>.cpp).
//
// Each writes its scene at size factor `size` (the SPD's -s) into the Writer
// it is handed, in the order the SPD program writes it. Sizes are checked by
// the caller (spd/spd.cpp) against the range each scene allows.
#pragma once

#include "spd/writer.h"

namespace lockstep::spd {

void balls(Writer& w, int size);
void cornell(Writer& w, int size);  // not an SPD program: the Cornell box (size 1 only)
void gears(Writer& w, int size);
void jacks(Writer& w, int size);
void lattice(Writer& w, int size);
void mount(Writer& w, int size);
void rings(Writer& w, int size);
void shells(Writer& w, int size);
void sombrero(Writer& w, int size);
void teapot(Writer& w, int size);
void tetra(Writer& w, int size);
void tree(Writer& w, int size);

// The SPD's usual sky-blue background (UNC sky blue), shared by most scenes.
inline constexpr Vec3 kSkyBlue = {0.078, 0.361, 0.753};

}  // namespace lockstep::spd
