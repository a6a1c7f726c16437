// lockstep: the command-line tool.
//
//   lockstep render SCENE [--impl NAME] [--size WxH] [--threads N] -o OUT
//   lockstep diff A B [--fail T] [--failpercent P] [--warn W] [--heatmap OUT]
//   lockstep verify [CORPUS_DIR] [--report DIR] [--impl NAME]... [--filter SUBSTR]
//
// main() only dispatches and turns exceptions into exit codes (app/cli.h).
#include <embree3/rtcore_config.h>
#include "optimized/ray_cast_simd.h"
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "app/cli.h"
#include "app/verify.h"  // merge_reports_main
#include "core/large_buffer.h"
#include "core/process_memory.h"
#include "io/oiio.h"

namespace cli = lockstep::cli;

namespace lockstep::cli {
int spd_main(Args args);  // app/spd.cpp
}  // namespace lockstep::cli

namespace {

void print_help() {
  std::printf(
      "lockstep %s: textbook graphics algorithms against optimized ones, proven to agree.\n"
      "\n"
      "usage:\n"
      "  lockstep render INPUT [--impl NAME] [--size WxH] [--threads N] -o OUT\n"
      "      render an input (.nff scene, .stack of layers, .texscene, ...) with one implementation\n"
      "      of its family; the format follows OUT's extension\n"
      "  lockstep composite LAYER... | --stack FILE [--alpha straight|premultiplied] [--order ftb|btf]\n"
      "                   [--impl NAME] [--threads N] -o OUT\n"
      "      composite RGBA layers (front first) with 'over'\n"
      "  lockstep isosurface VOLUME --iso C [--impl NAME] [--threads N] -o MESH\n"
      "      extract an isosurface by marching cubes (.nrrd/.nhdr volume or .field) into a mesh\n"
      "  lockstep volume VOLUME --tf TF [--algo raycast|splat|iso] [--step DT] [--view AZ,EL] -o IMAGE\n"
      "      render a volume: ray casting, splatting, or the isosurface ray cast\n"
      "  lockstep texture SCENE [--filter F] [--texture SPEC] [--wrap W] [--impl NAME] -o IMAGE\n"
      "      filter a texture on a plane under perspective (.texscene): point .. anisotropic, EWA\n"
      "  lockstep radiosity SCENE [--patch-area A | --error E] [--form-factors rays|hemicube|exact] [--solver S] -o IMAGE\n"
      "      solve an NFF scene with emitters for radiosity, drawn through the z-buffer\n"
      "  lockstep trace SCENE --pixel X,Y [--depth N] [--impl reference|embree]\n"
      "      print the ray tree of one pixel as the ray tracer (render --algo ray_trace) traces it\n"
      "  lockstep diff A B | DIR_A DIR_B | --list FILE [--fail T] [--failpercent P] [--warn W] [--heatmap OUT]\n"
      "      compare two images (idiff style), or many pairs in one call; exit 0 when all agree, 1 when not\n"
      "  lockstep verify [CORPUS_DIR] [--report DIR] [--impl NAME]... [--filter SUBSTR]\n"
      "      render every corpus case with every implementation, check against the reference,\n"
      "      the golden images and analytic judges, and write a report\n"
      "  lockstep spd NAME [--size N] [--tess] -o FILE.nff\n"
      "      write one of Eric Haines' SPD scenes (balls, gears, mount, teapot, ...) as NFF\n"
      "  lockstep merge-reports OUT_DIR REPORT_DIR...\n"
      "      join the reports of a sharded verify run (--shard K/N) into one page, JSON and JUnit\n"
      "  lockstep families\n"
      "      print the registered families' names, one a line (for scripts)\n"
      "\n"
      "families and implementations (registry/registry.h): %s\n"
      "\n"
      "options: --help (also after a subcommand), --version\n"
      "environment: LOCKSTEP_SPD_DIR, LOCKSTEP_VOLUMES_DIR (data beside the repository; SPD scenes are\n"
      "  generated when absent), LOCKSTEP_PEER_DIR (where the modules lockstep_oiio.so and the peer\n"
      "  rows' lockstep_peer_*.so are)\n"
      "exit codes: 0 ok, 1 differences/failures, 2 bad usage or bad input, 3 internal error\n",
      LOCKSTEP_VERSION, cli::all_impl_names().c_str());
}

void print_version() {
  // OpenImageIO's version as recorded beside lockstep_oiio.so when it was built
  // (io/oiio.h): printing it does not open the module and its ~250 libraries.
  std::string oiio = lockstep::oiio::recorded_version();
  if (oiio.empty()) oiio = "(module lockstep_oiio.so not found: image files cannot be read or written)";
  std::printf("lockstep %s (simd: Highway target %s; embree %d.%d.%d; OpenImageIO %s)\n", LOCKSTEP_VERSION,
              lockstep::opt::simd::target_name(), RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH,
              oiio.c_str());
  // Memory (issue #35): whether large buffers go on huge pages here.
  std::printf("  memory: %s\n", lockstep::huge_page_summary().c_str());
  // Peer rows, from the registry (core/family.h PeerRow): a module beside the
  // binary or a program, built only where its library was found at configure
  // time. Their versions were recorded then: nothing here loads a peer library.
  for (const lockstep::Family& f : lockstep::registry().families)
    for (const lockstep::PeerRow& p : f.peer_rows) {
      if (p.built)
        std::printf("  %s row: built (%s; %s)\n", p.row.c_str(), p.version.c_str(), p.runs_as.c_str());
      else
        std::printf("  %s row: not built (%s)\n", p.row.c_str(), p.missing.c_str());
    }
  // Every family and implementation built into this binary; peers are production libraries.
  for (const lockstep::Family& f : lockstep::registry().families) {
    std::printf("  %-10s", std::string(f.name).c_str());
    for (const lockstep::FamilyImpl& i : f.impls)
      std::printf(" %s%s", std::string(i.name).c_str(),
                  i.peer.empty() ? "" : (" [peer: " + std::string(i.peer) + "]").c_str());
    std::printf("\n");
  }
}

// `lockstep families`: the registry's family names, one a line, nothing else
// (tests/layout_check.py reads it: every family has its docs page).
int families_main(cli::Args args) {
  for (const std::string_view a : args) {
    if (a == "--help" || a == "-h") {
      std::printf(
          "usage: lockstep families\n"
          "  print the name of every registered family (registry/registry.h), one a line, in the\n"
          "  registry's order; `lockstep --version` lists each with its implementations\n");
      return cli::kExitOk;
    }
    if (cli::is_option(a)) cli::unknown_option(a);
    throw cli::UsageError("unexpected argument '" + std::string(a) + "'");
  }
  for (const lockstep::Family& f : lockstep::registry().families) std::printf("%s\n", std::string(f.name).c_str());
  return cli::kExitOk;
}

int run(int argc, char** argv, std::string& sub) {
  std::vector<std::string_view> args(argv + 1, argv + argc);
  if (args.empty()) throw cli::UsageError("missing subcommand (render, composite, isosurface, volume, texture, radiosity, trace, diff, verify, merge-reports, spd or families)");
  const std::string_view first = args.front();
  if (first == "--help" || first == "-h" || first == "help") {
    print_help();
    return cli::kExitOk;
  }
  if (first == "--version" || first == "-V") {
    print_version();
    return cli::kExitOk;
  }
  const cli::Args rest = cli::Args(args).subspan(1);
  sub = std::string(first);
  // --version works after a subcommand too (--help is each subcommand's own).
  for (const std::string_view a : rest) {
    if (a == "--") break;
    if (a == "--version" || a == "-V") {
      print_version();
      return cli::kExitOk;
    }
  }
  if (first == "render") return cli::render_main(rest);
  if (first == "diff") return cli::diff_main(rest);
  if (first == "verify") return cli::verify_main(rest);
  if (first == "merge-reports") return cli::merge_reports_main(rest);
  if (first == "composite") return cli::composite_main(rest);
  if (first == "isosurface") return cli::isosurface_main(rest);
  if (first == "texture") return cli::texture_main(rest);
  if (first == "volume") return cli::volume_main(rest);
  if (first == "radiosity") return cli::radiosity_main(rest);
  if (first == "trace") return cli::trace_main(rest);
  if (first == "spd") return cli::spd_main(rest);
  if (first == "families") return families_main(rest);
  sub.clear();
  if (cli::is_option(first)) cli::unknown_option(first);
  throw cli::UsageError("unknown subcommand '" + std::string(first) + "' (render, composite, isosurface, volume, texture, radiosity, trace, diff, verify, merge-reports, spd or families)");
}

}  // namespace

int main(int argc, char** argv) {
  // One command a process: what it frees, it reuses (core/process_memory.h).
  lockstep::keep_freed_memory();
  std::string sub;
  try {
    return run(argc, argv, sub);
  } catch (const lockstep::InputError& e) {
    std::fprintf(stderr, "lockstep: %s\n", e.what());
    return cli::kExitBadInput;
  } catch (const cli::UsageError& e) {
    const std::string who = sub.empty() ? "lockstep" : "lockstep " + sub;
    std::fprintf(stderr, "%s: %s (see %s --help)\n", who.c_str(), e.what(), who.c_str());
    return cli::kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "lockstep: out of memory\n");
    return cli::kExitInternal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lockstep: internal error: %s\n", e.what());
    return cli::kExitInternal;
  }
}
