// lockstep props/texture: the case's text form (props/texture/case.h).
#include "props/texture/case.h"

#include <sstream>

#include "core/error.h"
#include "props/gen/case_text.h"

namespace lockstep::props::texture {

namespace {

void put(std::ostream& s, const char* key, const Vec3& v) {
  s << key << ' ' << gen::hex(v.x) << ' ' << gen::hex(v.y) << ' ' << gen::hex(v.z) << '\n';
}
const char* wrap_name(Wrap w) { return w == Wrap::repeat ? "repeat" : w == Wrap::clamp ? "clamp" : "mirror"; }

}  // namespace

std::string write_case(const TexCase& c) {
  const TextureScene& sc = c.scene;
  std::ostringstream s;
  s << "filter " << c.filter << '\n';
  if (!c.tiles.empty()) s << "tiles " << c.tiles << '\n';
  s << "size " << sc.width << ' ' << sc.height << '\n';
  s << "wrap " << wrap_name(sc.texture.wrap) << '\n';
  put(s, "origin", sc.origin);
  put(s, "edge_s", sc.edge_s);
  put(s, "edge_t", sc.edge_t);
  s << "repeat " << gen::hex(sc.repeat_u) << ' ' << gen::hex(sc.repeat_v) << '\n';
  put(s, "from", sc.view.from);
  put(s, "at", sc.view.at);
  put(s, "up", sc.view.up);
  s << "angle " << gen::hex(sc.view.angle) << '\n';
  s << "hither " << gen::hex(sc.view.hither) << '\n';
  put(s, "background", sc.background);
  s << "texels " << sc.texture.width << ' ' << sc.texture.height << '\n';
  for (int j = 0; j < sc.texture.height; ++j) {
    for (int i = 0; i < sc.texture.width; ++i) {
      const float* t = sc.texture.texel(i, j);
      s << (i ? "  " : "") << gen::hex(t[0]) << ' ' << gen::hex(t[1]) << ' ' << gen::hex(t[2]) << ' ' << gen::hex(t[3]);
    }
    s << '\n';
  }
  return s.str();
}

TexCase read_case(const std::string& text, const std::string& file) {
  std::istringstream s(gen::without_comments(text));
  TexCase c;
  TextureScene& sc = c.scene;
  sc.source = file;
  auto fail = [&](const std::string& what) -> void { throw InputError(file, 0, "texture case: " + what); };
  auto num = [&](std::istream& in) {
    std::string w;
    if (!(in >> w)) fail("a number is missing");
    return std::strtod(w.c_str(), nullptr);
  };
  auto vec = [&](std::istream& in) {
    const double x = num(in), y = num(in);
    return Vec3{x, y, num(in)};
  };
  std::string key;
  while (s >> key) {
    if (key == "filter") s >> c.filter;
    else if (key == "tiles") std::getline(s >> std::ws, c.tiles);
    else if (key == "size") s >> sc.width >> sc.height;
    else if (key == "wrap") {
      std::string w;
      s >> w;
      sc.texture.wrap = w == "clamp" ? Wrap::clamp : w == "mirror" ? Wrap::mirror : Wrap::repeat;
    } else if (key == "origin") sc.origin = vec(s);
    else if (key == "edge_s") sc.edge_s = vec(s);
    else if (key == "edge_t") sc.edge_t = vec(s);
    else if (key == "repeat") {
      sc.repeat_u = num(s);
      sc.repeat_v = num(s);
    } else if (key == "from") sc.view.from = vec(s);
    else if (key == "at") sc.view.at = vec(s);
    else if (key == "up") sc.view.up = vec(s);
    else if (key == "angle") sc.view.angle = num(s);
    else if (key == "hither") sc.view.hither = num(s);
    else if (key == "background") sc.background = vec(s);
    else if (key == "texels") {
      s >> sc.texture.width >> sc.texture.height;
      if (!s || sc.texture.width < 1 || sc.texture.height < 1 || sc.texture.width > 4096 || sc.texture.height > 4096)
        fail("bad texel counts");
      sc.texture.rgba.resize(size_t(sc.texture.width) * sc.texture.height * 4);
      for (float& v : sc.texture.rgba) v = float(num(s));
    } else
      fail("unknown key '" + key + "'");
  }
  if (sc.texture.rgba.empty()) fail("no texels");
  if (sc.width < 1 || sc.height < 1) fail("no size");
  return c;
}

}  // namespace lockstep::props::texture
