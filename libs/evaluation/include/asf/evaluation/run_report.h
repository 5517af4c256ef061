#pragma once
/// \file run_report.h
/// The self-contained HTML report of one run, made from the files the run wrote
/// (Pipeline::outputFiles(): summary.json, timeseries.csv, map.png, regions.png,
/// decisions.csv, ...). Images are embedded (base64), plots are inline SVG, so the one
/// file can be mailed or archived.
#include <map>
#include <string>
#include <vector>

namespace asf::evaluation {

/// Writes RUN_DIR/report.html: the summary table, map.png and regions.png, and the plots
/// coverage vs distance, pose error vs distance, pose error / distance vs distance, per-stage
/// compute time. Missing inputs are noted in the report, not fatal (an interrupted run
/// still gets a report). Throws asf::Error naming the file only when report.html cannot be
/// written. Returns the report's path.
std::string writeRunReport(const std::string& run_dir);

/// Pieces shared by the run report and the experiment summary (asf/studies/experiment.h); HTML
/// escaping is asf::htmlEscape (text.h), atomic writes asf::writeFileAtomically (atomic_file.h).
namespace report {

/// A CSV file with a header line: its columns by name, numbers as doubles (NaN for empty
/// or non-numeric fields, and for fields missing from a short row). Throws InputError
/// naming the file when it cannot be read or has no header.
std::map<std::string, std::vector<double>> readCsvColumns(const std::string& path);

/// RFC 4648 base64 of `bytes` (for data: URLs).
std::string base64(const std::string& bytes);

/// An <img> element with the PNG file embedded (base64), or "" when it cannot be read.
std::string embeddedPng(const std::string& path, const std::string& alt);

/// The CSS every asf HTML report uses.
const char* css();

}  // namespace report

}  // namespace asf::evaluation
