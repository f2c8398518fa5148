// Reading the MOTChallenge layout and prediction files (mot_evaluation.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "jointflow/error.hpp"
#include "jointflow/mot_evaluation.hpp"

namespace jointflow::mot {

namespace fs = std::filesystem;

namespace {

/// Calls `row(line, where)` for each non-blank line of a text file, `where` = "file:line".
template <typename Row>
void forEachLine(const fs::path& file, Row row) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open the file");
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    row(line, file.string() + ":" + std::to_string(number));
  }
}

/// The comma-separated numbers of one MOT line (MOTChallenge writes commas; some tools write
/// spaces after them, which std::stod skips).
std::vector<double> parseNumbers(const std::string& line, const std::string& where) {
  std::vector<double> values;
  std::stringstream fields(line);
  std::string field;
  while (std::getline(fields, field, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(field, &used);
    } catch (const std::exception&) {
      throw Error(where + ": expected a number, got '" + field + "'");
    }
    if (field.find_first_not_of(" \t\r", used) != std::string::npos || !std::isfinite(v)) {
      throw Error(where + ": expected a number, got '" + field + "'");
    }
    values.push_back(v);
  }
  return values;
}

bool isInteger(double v) { return v == std::floor(v) && std::fabs(v) < 9e15; }

/// The id and box of a MOT row (columns 2-6), checked.
Box rowBox(const std::vector<double>& v, const std::string& where) {
  if (!isInteger(v[1])) throw Error(where + ": the id must be an integer");
  Box b;
  b.id = static_cast<std::int64_t>(v[1]);
  b.x = v[2], b.y = v[3], b.w = v[4], b.h = v[5];
  if (b.w < 0 || b.h < 0) throw Error(where + ": a box of negative width or height");
  return b;
}

/// A box's place in `frames`, or false for rows past the evaluated frames.
bool frameSlot(double frame, std::size_t num_frames, const std::string& where,
               std::size_t& slot) {
  if (!isInteger(frame) || frame < 1) {
    throw Error(where + ": the frame must be an integer >= 1, got " + std::to_string(frame));
  }
  slot = static_cast<std::size_t>(frame) - 1;
  return slot < num_frames;
}

/// Ids repeated in one frame make every figure meaningless: refused, naming the frame.
void checkUniqueIds(const Frames& frames, const std::string& file) {
  for (std::size_t f = 0; f < frames.size(); ++f) {
    std::set<std::int64_t> seen;
    for (const Box& b : frames[f]) {
      if (!seen.insert(b.id).second) {
        throw Error(file + ": id " + std::to_string(b.id) + " appears twice in frame " +
                    std::to_string(f + 1));
      }
    }
  }
}

/// seqinfo.ini's seqLength, or 0.
std::size_t seqLength(const fs::path& folder) {
  std::ifstream in(folder / "seqinfo.ini");
  std::string line;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos || line.compare(0, eq, "seqLength") != 0) continue;
    try {
      return static_cast<std::size_t>(std::stoul(line.substr(eq + 1)));
    } catch (const std::exception&) {
      throw Error((folder / "seqinfo.ini").string() + ": seqLength is not a number");
    }
  }
  return 0;
}

std::size_t countFiles(const fs::path& folder) {
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(folder)) n += entry.is_regular_file();
  return n;
}

GroundTruthSequence readSequence(const fs::path& folder) {
  const fs::path file = folder / "gt" / "gt.txt";
  std::vector<std::pair<std::size_t, Box>> rows;
  std::size_t last_frame = 0;
  forEachLine(file, [&](const std::string& line, const std::string& where) {
    const std::vector<double> v = parseNumbers(line, where);
    if (v.size() < 9) {
      throw Error(where + ": a ground-truth row has 9 columns (frame,id,x,y,w,h,flag,class," +
                  "visibility), got " + std::to_string(v.size()));
    }
    Box b = rowBox(v, where);
    b.flag = static_cast<int>(v[6]);
    b.cls = static_cast<int>(v[7]);
    b.visibility = v[8];
    std::size_t slot = 0;
    frameSlot(v[0], SIZE_MAX, where, slot);
    last_frame = std::max(last_frame, slot + 1);
    rows.emplace_back(slot, b);
  });
  std::size_t n = 0;
  if (fs::is_directory(folder / "img1")) {
    n = countFiles(folder / "img1");
  } else {
    n = seqLength(folder);
  }
  if (n == 0) n = last_frame;
  GroundTruthSequence seq;
  seq.name = folder.filename().string();
  seq.frames.resize(n);
  for (const auto& [slot, box] : rows) {
    if (slot < n) seq.frames[slot].push_back(box);
  }
  checkUniqueIds(seq.frames, file.string());
  return seq;
}

bool isSequence(const fs::path& folder) { return fs::is_regular_file(folder / "gt" / "gt.txt"); }

std::vector<fs::path> sequenceFolders(const fs::path& root) {
  std::vector<fs::path> found;
  if (isSequence(root)) return {root};
  if (!fs::is_directory(root)) return found;
  for (const auto& entry : fs::directory_iterator(root)) {
    if (!entry.is_directory()) continue;
    if (isSequence(entry.path())) {
      found.push_back(entry.path());
    } else if (entry.path().filename() == "train" || entry.path().filename() == "test") {
      for (const auto& inner : fs::directory_iterator(entry.path())) {
        if (inner.is_directory() && isSequence(inner.path())) found.push_back(inner.path());
      }
    }
  }
  std::sort(found.begin(), found.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  return found;
}

/// Ids for rows without one (-1): above every id of the file, so none collides.
void giveMissingIds(Frames& frames) {
  std::int64_t next = 0;
  for (const auto& f : frames) {
    for (const Box& b : f) next = std::max(next, b.id + 1);
  }
  for (auto& f : frames) {
    for (Box& b : f) {
      if (b.id == -1) b.id = next++;
    }
  }
}

Frames readMotText(const std::string& file, std::size_t num_frames) {
  Frames frames(num_frames);
  forEachLine(file, [&](const std::string& line, const std::string& where) {
    const std::vector<double> v = parseNumbers(line, where);
    if (v.size() < 6) {
      throw Error(where + ": a MOT row has at least 6 columns (frame,id,x,y,w,h[,conf,...]), got " +
                  std::to_string(v.size()));
    }
    Box b = rowBox(v, where);
    if (v.size() > 6) b.confidence = v[6];
    std::size_t slot = 0;
    if (frameSlot(v[0], num_frames, where, slot)) frames[slot].push_back(b);
  });
  return frames;
}

double jsonNumber(const nlohmann::json& object, const char* key, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) {
    throw Error(where + ": expected a number \"" + key + "\"");
  }
  return it->get<double>();
}

Frames readJsonLines(const std::string& file, std::size_t num_frames) {
  Frames frames(num_frames);
  forEachLine(file, [&](const std::string& line, const std::string& where) {
    nlohmann::json record;
    try {
      record = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw Error(where + ": not JSON (" + e.what() + ")");
    }
    if (!record.is_object()) throw Error(where + ": expected a JSON object per line");
    const double frame = jsonNumber(record, "frame", where);
    const auto objects = record.find("objects");
    if (objects == record.end() || !objects->is_array()) {
      throw Error(where + ": expected an array \"objects\"");
    }
    std::size_t slot = 0;
    // The product numbers frames from 0, MOT from 1.
    if (!frameSlot(frame + 1, num_frames, where, slot)) return;
    for (const auto& o : *objects) {
      if (!o.is_object()) throw Error(where + ": an object of \"objects\" is not a JSON object");
      // The same checks as a MOT row's: the numbers in MOT's column order.
      std::vector<double> v{frame + 1};
      for (const char* key : {"id", "x", "y", "w", "h"}) v.push_back(jsonNumber(o, key, where));
      Box b = rowBox(v, where);
      if (o.contains("confidence")) b.confidence = jsonNumber(o, "confidence", where);
      frames[slot].push_back(b);
    }
  });
  return frames;
}

bool isJsonFile(const fs::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".jsonl" || ext == ".json";
}

}  // namespace

std::vector<GroundTruthSequence> readGroundTruth(const std::string& path) {
  if (!fs::exists(path)) throw Error(path + ": no such file or folder");
  std::vector<GroundTruthSequence> sequences;
  for (const fs::path& folder : sequenceFolders(path)) sequences.push_back(readSequence(folder));
  if (sequences.empty()) {
    throw Error(path + ": no MOTChallenge sequence (a folder holding gt/gt.txt) in it");
  }
  return sequences;
}

Frames readPredictions(const std::string& file, std::size_t num_frames) {
  if (!fs::is_regular_file(file)) throw Error(file + ": no such file");
  Frames frames =
      isJsonFile(file) ? readJsonLines(file, num_frames) : readMotText(file, num_frames);
  giveMissingIds(frames);
  checkUniqueIds(frames, file);
  return frames;
}

std::string motLine(std::int64_t frame, const Box& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%lld,%lld,%.2f,%.2f,%.2f,%.2f,%.4f,-1,-1,-1",
                static_cast<long long>(frame), static_cast<long long>(b.id), b.x, b.y, b.w, b.h,
                b.confidence);
  return buf;
}

}  // namespace jointflow::mot
