// Log conversions: Rawseeds <-> rawlog, CARMEN -> rawlog (logic in libs/io).
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/io/rawlog_io.h>
#include <asf/io/carmen.h>
#include <asf/io/rawseeds.h>
#include <tclap/CmdLine.h>

#include <iomanip>
#include <iostream>

#include "commands.h"

namespace asf::app {

namespace {

void printStreams(const std::vector<io::StreamReport>& streams) {
  for (const auto& s : streams) {
    std::cout << "  " << std::left << std::setw(14) << s.stream << std::right << s.records
              << " records from " << s.lines << " lines of " << s.file;
    if (s.records > 0)
      std::cout << std::fixed << std::setprecision(6) << ", t " << s.t_first << " .. " << s.t_last
                << std::defaultfloat;
    std::cout << "\n";
    if (s.bad_lines > 0)
      std::cout << "  " << std::setw(14) << "" << s.bad_lines
                << " bad lines skipped (first: " << s.file << ":" << s.first_bad_line << ": "
                << s.first_bad_reason << ")\n";
  }
}

}  // namespace

int cmdRawseeds2Rawlog(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Converts a Rawseeds session (CSV streams, plain or .bz2) into a time-ordered "
      "observation-only MRPT rawlog: the SICK laser streams and ODOMETRY_XYT, merged; the "
      "ground-truth stream into an asf ground-truth file (--gt).",
      ' ', ASF_VERSION_STRING);
  TCLAP::ValueArg<std::string> dir("", "dir", "Folder of the stream files", true, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> dataset("", "dataset", "Session name, e.g. Bicocca_2009-02-25b",
                                       true, "", "NAME", cmd);
  TCLAP::MultiArg<std::string> laser("", "laser",
                                     "Laser stream, SICK_FRONT or SICK_REAR (repeatable; "
                                     "default SICK_FRONT)",
                                     false, "STREAM", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output rawlog (.gz: compressed)", false, "",
                                   "FILE.rawlog", cmd);
  TCLAP::ValueArg<std::string> gt("", "gt", "Also write the ground truth (timestamp x y phi)",
                                  false, "", "FILE", cmd);
  TCLAP::SwitchArg gt_only("", "gt-only",
                           "Convert only the ground-truth stream to --gt (no rawlog, no -o)", cmd);
  std::vector<std::string> gts{"GROUNDTRUTH", "GT-extended"};
  TCLAP::ValuesConstraint<std::string> gtc(gts);
  TCLAP::ValueArg<std::string> gt_stream("", "gt-stream", "Ground-truth stream for --gt", false,
                                         "GROUNDTRUTH", &gtc, cmd);
  TCLAP::SwitchArg skip("", "skip-bad-lines", "Skip and count malformed lines instead of failing",
                        cmd);
  TCLAP::SwitchArg quiet("q", "quiet", "No progress lines", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  if (gt_only.getValue() && (gt.getValue().empty() || !out.getValue().empty()))
    throw TCLAP::CmdLineParseException("needs --gt and no -o", "--gt-only");
  if (!gt_only.getValue() && out.getValue().empty())
    throw TCLAP::CmdLineParseException("required (or --gt-only with --gt)", "-o/--out");

  if (gt_only.getValue()) {
    const auto file =
        io::findRawseedsStream(dir.getValue(), dataset.getValue(), gt_stream.getValue());
    const auto s = io::rawseedsGroundTruthToFile(file, gt.getValue(), skip.getValue(),
                                                      quiet.getValue() ? nullptr : &std::cerr);
    std::cout << "rawseeds2rawlog: " << s.records << " ground-truth poses -> " << gt.getValue()
              << "\n";
    printStreams({s});
    return kOk;
  }

  io::RawseedsToRawlogOptions o;
  o.dir = dir.getValue();
  o.dataset = dataset.getValue();
  if (!laser.getValue().empty()) o.lasers = laser.getValue();
  o.output = out.getValue();
  o.gt_output = gt.getValue();
  o.gt_stream = gt_stream.getValue();
  o.skip_bad_lines = skip.getValue();
  o.progress = quiet.getValue() ? nullptr : &std::cerr;
  const auto r = io::rawseedsToRawlog(o);
  std::cout << "rawseeds2rawlog: " << r.scans << " scans and " << r.odometry
            << " odometry readings -> " << o.output;
  if (!o.gt_output.empty())
    std::cout << "; " << r.gt_poses << " ground-truth poses -> " << o.gt_output;
  std::cout << " in " << std::fixed << std::setprecision(1) << r.wall_time_s << " s\n"
            << std::defaultfloat;
  printStreams(r.streams);
  return kOk;
}

int cmdRawlogNormalize(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Rewrites a rawlog (either layout, .gz or not) as asf reads it: action/sensory-frame "
      "pairs, one per scan of the chosen laser, every odometry action timestamped with its "
      "scan's time and carrying its Gaussian covariance. MRPT tools such as icp-slam refuse "
      "logs whose odometry has no timestamp (e.g. graphslam-engine-demos/.../simul.rawlog).",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> in("input", "Input rawlog", true, "", "IN.rawlog", cmd);
  TCLAP::UnlabeledValueArg<std::string> out("output", "Output rawlog (.gz: compressed)", true, "",
                                            "OUT.rawlog", cmd);
  TCLAP::ValueArg<std::string> label("", "laser-label",
                                     "Scans of this sensorLabel (default: the first laser seen)",
                                     false, "", "LABEL", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  io::RawlogReaderOptions o;
  o.laser_label = label.getValue();
  io::RawlogReader reader(in.getValue(), o);
  // Beside the output, renamed over it at the end: a failure never truncates the old file.
  AtomicOutput target(out.getValue(), "rawlog");
  std::size_t scans = 0, frames = 0;
  {
    io::RawlogWriter writer(target.file());
    while (auto f = reader.next()) {
      scans += f->scan ? 1 : 0;
      writer.write(*f);
    }
    writer.close();  // throws when anything written was lost
    frames = writer.framesWritten();
  }
  target.commit();
  std::cout << "rawlog-normalize: " << frames << " frames (" << scans
            << " scans) written to " << out.getValue() << "\n";
  return kOk;
}

int cmdRawlog2Rawseeds(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Writes a rawlog (and an asf ground-truth file) as Rawseeds CSV streams: "
      "<NAME>-SICK_FRONT.csv, <NAME>-ODOMETRY_XYT.csv (odometry increments integrated), "
      "<NAME>-GROUNDTRUTH.csv. Scans must have 181 rays over 180 degrees. For testing the "
      "Rawseeds reader without the real streams.",
      ' ', ASF_VERSION_STRING);
  TCLAP::ValueArg<std::string> rawlog("", "rawlog", "Input rawlog", true, "", "FILE", cmd);
  TCLAP::ValueArg<std::string> gt("", "gt", "Ground-truth file (timestamp x y phi)", false, "",
                                  "FILE", cmd);
  TCLAP::ValueArg<std::string> dir("", "dir", "Output folder (created)", true, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> dataset("", "dataset", "File name prefix", true, "", "NAME", cmd);
  TCLAP::ValueArg<std::string> label("", "laser-label",
                                     "Scans of this sensorLabel (default: the first laser seen)",
                                     false, "", "LABEL", cmd);
  TCLAP::SwitchArg bz2("", "bz2", "Write .csv.bz2 (as Rawseeds distributes them)", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  io::RawlogToRawseedsOptions o;
  o.rawlog = rawlog.getValue();
  o.gt_input = gt.getValue();
  o.dir = dir.getValue();
  o.dataset = dataset.getValue();
  o.laser_label = label.getValue();
  o.bz2 = bz2.getValue();
  const auto r = io::rawlogToRawseeds(o);
  std::cout << "rawlog2rawseeds: " << r.frames << " frames: " << r.scans << " scan lines, "
            << r.odometry_lines << " odometry lines";
  if (!o.gt_input.empty()) std::cout << ", " << r.gt_lines << " ground-truth lines";
  std::cout << "\n";
  for (const auto& f : r.files) std::cout << "  " << f << "\n";
  return kOk;
}

namespace {

/// asf carmen2rawlog's options, added to `cmd` in declaration order (--help's order depends on it).
struct CarmenArgs {
  explicit CarmenArgs(TCLAP::CmdLine& parser) : cmd(parser) {}

  TCLAP::CmdLine& cmd;
  TCLAP::ValueArg<std::string> in{"i", "in", "CARMEN log (.gz: gunzipped)", true, "", "LOG", cmd};
  TCLAP::ValueArg<std::string> out{"o", "out", "Output rawlog (.gz: compressed)", true, "",
                                   "FILE.rawlog", cmd};
  TCLAP::ValueArg<std::string> gt{"", "gt", "Also write the ground truth (timestamp x y phi)",
                                  false, "", "FILE", cmd};
  TCLAP::SwitchArg synth{"", "synth-odometry",
                         "Synthesize noisy odometry from the logged poses (corrected logs)", cmd};
  TCLAP::SwitchArg odom_lines{"", "odom-lines", "Odometry from the ODOM lines", cmd};
  TCLAP::ValueArg<std::uint64_t> seed{"", "seed", "Seed of --synth-odometry", false, 1, "N", cmd};
  const mapping::OdometryNoiseModel def{};  // the defaults of --a1 .. --min-std-phi
  TCLAP::ValueArg<double> a1{"", "a1", "Odometry model: x/y std per metre [m/m]", false, def.a1,
                             "A", cmd};
  TCLAP::ValueArg<double> a2{"", "a2", "Odometry model: x/y std per degree [m/deg]", false, def.a2,
                             "A", cmd};
  TCLAP::ValueArg<double> a3{"", "a3", "Odometry model: phi std per metre [deg/m]", false, def.a3,
                             "A", cmd};
  TCLAP::ValueArg<double> a4{"", "a4", "Odometry model: phi std per degree [deg/deg]", false,
                             def.a4, "A", cmd};
  TCLAP::ValueArg<double> min_xy{"", "min-std-xy", "Odometry model: minimum x/y std [m]", false,
                                 def.min_std_xy, "S", cmd};
  TCLAP::ValueArg<double> min_phi{"", "min-std-phi", "Odometry model: minimum phi std [deg]", false,
                                  def.min_std_phi_deg, "S", cmd};
  TCLAP::ValueArg<double> fov{"", "fov-deg",
                              "FLASER field of view [deg] (default: from PARAM lines, else 180)",
                              false, 0, "DEG", cmd};
  TCLAP::ValueArg<double> max_range{
      "", "max-range", "Maximum range [m] (default: from the log, else 80)", false, 0, "M", cmd};
  std::vector<std::string> stamp_modes{"auto", "log", "order"};
  TCLAP::ValuesConstraint<std::string> stamp_allowed{stamp_modes};
  TCLAP::ValueArg<std::string> stamps{
      "", "timestamps",
      "Scan timestamps: log (the laser lines' ipc_timestamp), order (the log's order, "
      "--scan-period apart), auto (log unless a stamp is not a time or more than 10% do not "
      "increase)",
      false, "auto", &stamp_allowed, cmd};
  TCLAP::ValueArg<double> period{"", "scan-period",
                                 "Seconds between scans when stamped by order (default: the "
                                 "log's median step if steady, else 1)",
                                 false, 0, "S", cmd};
  TCLAP::SwitchArg skip{"", "skip-bad-lines", "Skip and count malformed lines instead of failing",
                        cmd};
  TCLAP::SwitchArg quiet{"q", "quiet", "No progress lines", cmd};
};

/// The option values carmen2rawlog refuses, as command-line errors.
void checkCarmenArgs(const CarmenArgs& a) {
  if (a.synth.getValue() && a.odom_lines.getValue())
    throw TCLAP::CmdLineParseException("use one of them", "--synth-odometry/--odom-lines");
  for (const auto* v :
       {&a.a1, &a.a2, &a.a3, &a.a4, &a.min_xy, &a.min_phi, &a.fov, &a.max_range, &a.period})
    if (!(v->getValue() >= 0)) throw TCLAP::CmdLineParseException("must be >= 0", v->getName());
}

/// The conversion the options ask for.
io::CarmenToRawlogOptions carmenOptions(const CarmenArgs& a) {
  io::CarmenToRawlogOptions o;
  o.input = a.in.getValue();
  o.output = a.out.getValue();
  o.gt_output = a.gt.getValue();
  using Mode = io::CarmenToRawlogOptions::Odometry;
  o.odometry = a.synth.getValue()        ? Mode::Synthetic
               : a.odom_lines.getValue() ? Mode::OdomLines
                                         : Mode::Laser;
  o.seed = a.seed.getValue();
  o.model.a1 = a.a1.getValue();
  o.model.a2 = a.a2.getValue();
  o.model.a3 = a.a3.getValue();
  o.model.a4 = a.a4.getValue();
  o.model.min_std_xy = a.min_xy.getValue();
  o.model.min_std_phi_deg = a.min_phi.getValue();
  o.fov_deg = a.fov.getValue();
  o.max_range = a.max_range.getValue();
  using Stamps = io::CarmenToRawlogOptions::Timestamps;
  o.timestamps = a.stamps.getValue() == "log"     ? Stamps::Log
                 : a.stamps.getValue() == "order" ? Stamps::Order
                                                  : Stamps::Auto;
  o.scan_period_s = a.period.getValue();
  o.skip_bad_lines = a.skip.getValue();
  o.progress = a.quiet.getValue() ? nullptr : &std::cerr;
  return o;
}

void printCarmenReport(const io::CarmenToRawlogOptions& o,
                       const io::CarmenToRawlogReport& r, bool synthesized) {
  std::cout << "carmen2rawlog: " << r.scans << " scans (" << r.laser_message << ", " << r.rays
            << " rays over " << r.aperture_deg << " deg) and " << r.odometry << " odometry readings"
            << (synthesized ? " (synthesized)" : "") << " -> " << o.output;
  if (!o.gt_output.empty())
    std::cout << "; " << r.gt_poses << " ground-truth poses -> " << o.gt_output;
  std::cout << " in " << std::fixed << std::setprecision(2) << r.wall_time_s << " s\n"
            << std::defaultfloat;
  std::cout << "  " << r.lines << " lines";
  for (const auto& [name, n] : r.ignored) std::cout << ", " << n << " " << name << " skipped";
  std::cout << "\n";
  if (r.stamped_by_order)
    std::cout << "  scans stamped from the log's order, " << r.scan_period_s << " s apart ("
              << r.stamps_bad << " laser timestamps not a time, " << r.stamps_not_increasing
              << " not increasing)\n";
  if (r.raised_timestamps)
    std::cout << "  " << r.raised_timestamps
              << " scans stamped before the previous record: moved just after it\n";
  if (r.odom_dropped)
    std::cout << "  " << r.odom_dropped << " ODOM lines going back in time dropped\n";
  if (r.bad_lines)
    std::cout << "  " << r.bad_lines << " bad lines skipped (first: " << o.input << ":"
              << r.first_bad_line << ": " << r.first_bad_reason << ")\n";
}

}  // namespace

int cmdCarmen2Rawlog(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Converts a CARMEN log (FLASER or ROBOTLASER1, ODOM; plain or .gz) into an "
      "observation-only MRPT rawlog; --gt writes the logged laser poses (the corrected poses "
      "in \"corrected\" logs) as ground truth. Odometry: the pose in each laser line, the ODOM "
      "lines (--odom-lines), or synthesized (--synth-odometry) from the logged poses with "
      "Gaussian noise of MRPT's odometry model.",
      ' ', ASF_VERSION_STRING);
  CarmenArgs args(cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  checkCarmenArgs(args);

  const io::CarmenToRawlogOptions o = carmenOptions(args);
  const auto r = io::carmenToRawlog(o);
  for (const auto& w : r.warnings) std::cerr << "carmen2rawlog: warning: " << w << "\n";

  printCarmenReport(o, r, args.synth.getValue());
  return kOk;
}

}  // namespace asf::app
