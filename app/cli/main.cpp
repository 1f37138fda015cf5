// relume: every stage headless. Progress on stderr, results as files; Ctrl-C cancels cleanly.
#include <QCoreApplication>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "relume/geometry/error.h"

namespace {
std::atomic<bool>* g_cancel = nullptr;  // the one thing a signal handler may touch
extern "C" void onSigint(int) {
  if (g_cancel) g_cancel->store(true);
}

void usage() {
  std::fprintf(stderr,
               "usage: relume <command> [options]\n"
               "  solve  ROOM --json OUT.json [--eps X] [--min-area A] [--oracle bf|bfv] [--rays N]\n"
               "  render ROOM --camera NAME -o IMG.exr|png [--show leaves|links|visibility] [--eps X]\n"
               "  bench  ROOM --json OUT.json [--runs N]\n"
               "  import ROOM -o PROJECT      (write a Relume project)\n"
               "  check ROOM                  (read it as every command would; exit 0 if all of it reads)\n"
               "  preprocess ROOM -o PROJECT  (textures, estimates, real shadows removed)\n"
               "  relight PROJECT --lamp A=0 [--lamp B=2] [--virtual-lamp F] [--virtual-object F]\n"
               "          [--method full|ratio-only] -o IMG.exr|png\n"
               "  evaluate BUNDLE --out DIR   (every variant vs its truth image: report.json)\n"
               "  compare RENDERING.exr BUNDLE --truth VARIANT  (the benchmark's PSNR)\n"
               "  reconstruct PHOTOS_DIR --out WORKSPACE [--scale P1,P2,M --floor P1,P2,P3]  (COLMAP)\n"
               "  align MODEL --to REFERENCE [-o ALIGNED]  (camera-centre errors after a similarity fit)\n"
               "  triangulate WORKSPACE --clicks CLICKS.json -o PROJECT  (polygons from clicked corners)\n"
               "  hdr-merge IMAGES... -o OUT.exr [--times T1,T2,..|--ev EV1,EV2,..]\n"
               "  calibrate CHECKERBOARD_DIR --pattern 9x6 --square 0.025 [-o intrinsics.json]\n"
               "  sky FISHEYE.exr [--projection equidistant|equisolid] [--fov 180] [--regions 64]  (sun, sky regions)\n"
               "  daylight-basis ROOM [--regions 64] [--exact] [--json OUT.json]  (basis solutions per sky region)\n"
               "  daylight-basis ROOM -o PROJECT  (a daylight room kept with its session: opens without solving)\n"
               "  photometry FILE.ies|FILE.ldt [--json OUT.json]  (a luminaire's flux and shape)\n"
               "  ibr-fan MESH -o FAN [--views 96] [--size 256] [--rings 15,45,75] [--no-dither] [--up y]\n"
               "          (an image-based object's fan, for relight --virtual-object)\n"
               "ROOM: a bundle folder (scene.json), a Relume project, or an .obj with its .json.\n"
               "Run 'relume <command> --help' for a command's options.\n");
}
}  // namespace

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);
  QCoreApplication::setApplicationName("relume");
  QCoreApplication::setApplicationVersion("0.1");
  const QStringList args = QCoreApplication::arguments();
  if (args.size() < 2 || args[1] == "-h" || args[1] == "--help") {
    usage();
    return args.size() < 2 ? 2 : 0;
  }
  relume::Progress progress([last = std::string()](double f, const std::string& text) mutable {
    if (text != last) {
      std::fprintf(stderr, "[%3d%%] %s\n", int(f * 100 + 0.5), text.c_str());
      last = text;
    }
  });
  g_cancel = progress.cancelFlag();
  std::signal(SIGINT, onSigint);
  std::signal(SIGTERM, onSigint);
  const QString cmd = args[1];
  QStringList rest = args;
  rest.removeAt(1);
  try {
    if (cmd == "solve") return relume::cli::solveCommand(rest, progress);
    if (cmd == "render") return relume::cli::renderCommand(rest, progress);
    if (cmd == "bench") return relume::cli::benchCommand(rest, progress);
    if (cmd == "import") return relume::cli::importCommand(rest, progress);
    if (cmd == "check") return relume::cli::checkCommand(rest, progress);
    if (cmd == "preprocess") return relume::cli::preprocessCommand(rest, progress);
    if (cmd == "relight") return relume::cli::relightCommand(rest, progress);
    if (cmd == "evaluate") return relume::cli::evaluateCommand(rest, progress);
    if (cmd == "compare") return relume::cli::compareCommand(rest, progress);
    if (cmd == "reconstruct") return relume::cli::reconstructCommand(rest, progress);
    if (cmd == "align") return relume::cli::alignCommand(rest, progress);
    if (cmd == "triangulate") return relume::cli::triangulateCommand(rest, progress);
    if (cmd == "hdr-merge") return relume::cli::hdrMergeCommand(rest, progress);
    if (cmd == "calibrate") return relume::cli::calibrateCommand(rest, progress);
    if (cmd == "sky") return relume::cli::skyCommand(rest, progress);
    if (cmd == "daylight-basis") return relume::cli::daylightBasisCommand(rest, progress);
    if (cmd == "photometry") return relume::cli::photometryCommand(rest, progress);
    if (cmd == "ibr-fan") return relume::cli::ibrFanCommand(rest, progress);
    std::fprintf(stderr, "relume: unknown command '%s'\n", qPrintable(cmd));
    usage();
    return 2;
  } catch (const relume::Cancelled&) {
    std::fprintf(stderr, "relume: cancelled; nothing was written\n");
    return 130;
  } catch (const relume::Error& e) {
    std::fprintf(stderr, "relume: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relume: internal error: %s\n", e.what());
    return 3;
  }
}
