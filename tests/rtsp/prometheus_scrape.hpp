// A scrape of jointflow-track's /metrics (--metrics-port), as Prometheus makes it: an HTTP GET
// on 127.0.0.1, the text format parsed into its samples.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <map>
#include <sstream>
#include <string>

namespace jointflow::test {

/// The HTTP status and body of GET @path on 127.0.0.1:@port; status 0 when nothing answered.
struct HttpAnswer {
  int status = 0;
  std::string headers, body;
};

inline HttpAnswer httpGet(int port, const std::string& path) {
  HttpAnswer answer;
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return answer;
  timeval timeout{5, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(static_cast<uint16_t>(port));
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return answer;
  }
  const std::string request =
      "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  if (send(fd, request.data(), request.size(), 0) != static_cast<ssize_t>(request.size())) {
    close(fd);
    return answer;
  }
  std::string text;
  char buffer[8192];
  for (ssize_t n; (n = recv(fd, buffer, sizeof buffer, 0)) > 0;) text.append(buffer, n);
  close(fd);
  const size_t end = text.find("\r\n\r\n");
  if (text.rfind("HTTP/1.", 0) != 0 || end == std::string::npos) return answer;
  answer.status = std::stoi(text.substr(9, 3));
  answer.headers = text.substr(0, end);
  answer.body = text.substr(end + 4);  // Connection: close, so the body is the rest
  return answer;
}

/// The samples of a Prometheus text page: "name{labels}" (as written) -> value; the # HELP and
/// # TYPE lines by metric name.
struct Scrape {
  std::map<std::string, double> samples;
  std::map<std::string, std::string> types;
  std::map<std::string, int> helps;

  bool has(const std::string& key) const { return samples.count(key) > 0; }
  double at(const std::string& key) const {
    const auto it = samples.find(key);
    return it == samples.end() ? -1.0 : it->second;
  }
};

inline Scrape parseScrape(const std::string& text) {
  Scrape s;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    std::istringstream words(line);
    std::string first, name, rest;
    if (line[0] == '#') {
      words >> first >> first >> name >> rest;  // "#", HELP|TYPE, name, text
      if (line.rfind("# TYPE ", 0) == 0) s.types[name] = rest;
      if (line.rfind("# HELP ", 0) == 0) s.helps[name]++;
      continue;
    }
    const size_t space = line.rfind(' ');
    s.samples[line.substr(0, space)] = std::stod(line.substr(space + 1));
  }
  return s;
}

}  // namespace jointflow::test
