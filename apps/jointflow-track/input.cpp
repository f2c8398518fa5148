// Input discovery for jointflow-track (input.hpp).
#include "input.hpp"

#include <gst/gst.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <regex>

#include "jointflow/error.hpp"

namespace fs = std::filesystem;

namespace jointflow::cli {
namespace {

FrameSequence numberedFrames(const fs::path& folder) {
  static const std::regex numbered(R"(^(.*?)(\d+)(\.(jpe?g|png))$)", std::regex::icase);
  struct Entry {
    std::string prefix, digits, suffix;
    long number;
  };
  std::vector<Entry> entries;
  for (const auto& e : fs::directory_iterator(folder)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && std::regex_match(name, m, numbered))
      entries.push_back({m[1], m[2], m[3], std::stol(m[2])});
  }
  if (entries.empty())
    throw Error(folder.string() +
                ": no numbered .jpg or .png frames (expected e.g. 000000.jpg, 000001.jpg, ...)");
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.number < b.number; });
  const Entry& f = entries.front();
  const bool fixed_width = std::all_of(entries.begin(), entries.end(), [&](const Entry& e) {
    return e.digits.size() == f.digits.size();
  });
  FrameSequence seq;
  for (size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    if (e.prefix != f.prefix || e.suffix != f.suffix)
      throw Error(folder.string() + ": frames \"" + f.prefix + f.digits + f.suffix + "\" and \"" +
                  e.prefix + e.digits + e.suffix +
                  "\" are not named alike; expected one numbered sequence");
    if (e.number != f.number + static_cast<long>(i))
      throw Error(folder.string() + ": frame " + std::to_string(f.number + i) +
                  " is missing (the numbers must be consecutive)");
    seq.names.push_back(e.prefix + e.digits + e.suffix);
  }
  std::string number = fixed_width ? "%0" + std::to_string(f.digits.size()) + "d" : "%d";
  // multifilesrc runs the pattern through printf: a literal '%' must be doubled.
  const std::string prefix = std::regex_replace(f.prefix, std::regex("%"), "%%");
  seq.pattern = (folder / (prefix + number + f.suffix)).string();
  seq.first = static_cast<int>(f.number);
  seq.last = static_cast<int>(entries.back().number);
  const std::string ext = f.suffix;
  seq.caps = (ext == ".png" || ext == ".PNG") ? "image/png" : "image/jpeg";
  return seq;
}

std::string uriScheme(const std::string& uri) {
  gchar* scheme = gst_uri_get_protocol(uri.c_str());
  std::string s = scheme ? scheme : "";
  g_free(scheme);
  return s;
}

// rtspsrc's schemes: rtspt:// asks for TCP, rtspu:// for UDP, rtsps:// for TLS.
bool isRtspScheme(const std::string& s) {
  return s == "rtsp" || s == "rtspt" || s == "rtspu" || s == "rtsps" || s == "rtspst" ||
         s == "rtspsu";
}

// An rtsp:// address must name a host (and a port that exists): rtspsrc would otherwise fail
// only once the pipeline runs, with a message that does not say what is wrong with it.
void checkRtspUri(const std::string& text, const std::string& shown) {
  const std::string expected =
      ": not a valid RTSP address (expected rtsp://[user:password@]host[:port]/path)";
  GstUri* uri = gst_uri_from_string(text.c_str());
  if (!uri) throw Error(shown + expected);
  const char* host = gst_uri_get_host(uri);
  const bool has_host = host && *host;
  const guint port = gst_uri_get_port(uri);
  gst_uri_unref(uri);
  if (!has_host) throw Error(shown + expected + ": no host");
  if (port != GST_URI_NO_PORT && (port == 0 || port > 65535))
    throw Error(shown + expected + ": port " + std::to_string(port) + " is out of range");
  if (text.find_first_of(" \t\r\n") != std::string::npos)
    throw Error(shown + expected + ": white space in it");
}

}  // namespace

bool isLiveUri(const std::string& uri) {
  const std::string s = uriScheme(uri);
  return isRtspScheme(s) || s == "udp" || s == "srt" || s == "rtmp" || s == "v4l2";
}

std::string redactUri(const std::string& text) {
  GstUri* uri = gst_uri_is_valid(text.c_str()) ? gst_uri_from_string(text.c_str()) : nullptr;
  if (!uri) return text;
  const char* userinfo = gst_uri_get_userinfo(uri);
  std::string shown = text;
  if (userinfo && std::strchr(userinfo, ':')) {
    const std::string user(userinfo, std::strchr(userinfo, ':'));
    const std::string from = std::string(userinfo) + "@";
    const size_t at = shown.find(from);
    if (at != std::string::npos) shown.replace(at, from.size(), user + ":***@");
  }
  gst_uri_unref(uri);
  return shown;
}

Input resolveInput(const std::string& text) {
  Input in;
  in.description = text;
  if (gst_uri_is_valid(text.c_str())) {
    in.uri = text;
    // Messages and logs show the address without its password.
    in.description = redactUri(text);
    if (isRtspScheme(uriScheme(text))) checkRtspUri(text, in.description);
    gchar* location = gst_uri_get_location(text.c_str());
    const fs::path p(location ? location : text);
    g_free(location);
    in.sequence_name = p.stem().string();
    in.file_prefix = in.sequence_name + "/";
    return in;
  }
  const fs::path path(text);
  if (fs::is_directory(path)) {
    in.frames = numberedFrames(path);
    const fs::path canonical = fs::weakly_canonical(path);
    in.sequence_name = canonical.filename().string();
    // PoseTrack ground truth names frames "images/<split>/<sequence>/000000.jpg".
    const fs::path split = canonical.parent_path();
    in.file_prefix = split.parent_path().filename() == "images"
                         ? "images/" + split.filename().string() + "/" + in.sequence_name + "/"
                         : in.sequence_name + "/";
    return in;
  }
  if (!fs::exists(path))
    throw Error(text +
                ": no such file or folder (expected a video file, a URI or a folder of "
                "numbered frames)");
  GError* error = nullptr;
  gchar* uri = gst_filename_to_uri(text.c_str(), &error);
  if (!uri) {
    const std::string message = error ? error->message : "invalid file name";
    g_clear_error(&error);
    throw Error(text + ": " + message);
  }
  in.uri = uri;
  g_free(uri);
  in.sequence_name = path.stem().string();
  in.file_prefix = in.sequence_name + "/";
  return in;
}

}  // namespace jointflow::cli
