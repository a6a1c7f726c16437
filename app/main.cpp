// PLACEHOLDER main for bring-up
#include <cstdio>
#include "core/nff.h"
#include "core/pairs.h"
#include "core/error.h"
int main(int argc, char** argv) {
  using namespace lockstep;
  try {
    Scene s = read_nff(argv[1]);
    RenderOptions o; o.width = o.height = argc > 3 ? atoi(argv[3]) : 256;
    for (auto& impl : pairs().ray_cast.impls) {
      if (impl.name == "embree") continue;
      RenderStats st;
      Image im = impl.fn.render(s, o, &st);
      write_image(im, std::string(argv[2]) + "-" + std::string(impl.name) + ".png");
      printf("%s %.3fs\n", std::string(impl.name).c_str(), st.trace_seconds);
    }
  } catch (const InputError& e) { fprintf(stderr, "%s\n", e.what()); return 2; }
}
