// Test helper: writes a tiny ONNX model whose outputs are given tensors, whatever the input, by
// encoding the protobuf by hand (the wire format is simple and this avoids a protobuf or Python
// dependency in the test suite). The graph:
//   input [1,3,H,W] -> GlobalAveragePool -> Conv 1x1 (weights 1/255, 0, 0) -> [1,1,1,1] (= 1 for
//   an image whose first channel is 255 everywhere) -> one ConvTranspose per output whose kernel
//   is that output's tensor -> outputs [1, C, h, w]. constantSequenceOnnx: the same for one
//   [1, C, N] output (a YOLO pose output), through a Reshape.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace jointflow::test {

class Proto {
 public:
  Proto& varint(int field, uint64_t v) {
    key(field, 0);
    raw(v);
    return *this;
  }
  Proto& bytes(int field, const std::string& s) {
    key(field, 2);
    raw(s.size());
    buf_ += s;
    return *this;
  }
  Proto& message(int field, const Proto& m) { return bytes(field, m.buf_); }
  const std::string& str() const { return buf_; }

 private:
  void key(int field, int wire) { raw((static_cast<uint64_t>(field) << 3) | wire); }
  void raw(uint64_t v) {
    do {
      uint8_t b = v & 0x7f;
      v >>= 7;
      if (v) b |= 0x80;
      buf_ += static_cast<char>(b);
    } while (v);
  }
  std::string buf_;
};

inline Proto onnxTensor(const std::string& name, const std::vector<int64_t>& dims,
                        const std::vector<float>& values) {
  Proto t;
  for (auto d : dims) t.varint(1, static_cast<uint64_t>(d));
  t.varint(2, 1);  // FLOAT
  t.bytes(8, name);
  t.bytes(9,
          std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float)));
  return t;
}

inline Proto onnxInt64Tensor(const std::string& name, const std::vector<int64_t>& values) {
  Proto t;
  t.varint(1, values.size());
  t.varint(2, 7);  // INT64
  t.bytes(8, name);
  t.bytes(9, std::string(reinterpret_cast<const char*>(values.data()),
                         values.size() * sizeof(int64_t)));  // little-endian, as ONNX stores it
  return t;
}

inline Proto onnxValueInfo(const std::string& name, const std::vector<std::string>& dims) {
  Proto shape;
  for (const auto& d : dims) {
    Proto dim;
    if (!d.empty() && d.find_first_not_of("0123456789") == std::string::npos) {
      dim.varint(1, std::stoull(d));
    } else {
      dim.bytes(2, d);
    }
    shape.message(1, dim);
  }
  Proto tensor_type;
  tensor_type.varint(1, 1).message(2, shape);
  Proto type;
  type.message(1, tensor_type);
  Proto vi;
  vi.bytes(1, name).message(2, type);
  return vi;
}

inline Proto onnxIntsAttr(const std::string& name, const std::vector<int64_t>& ints) {
  Proto a;
  a.bytes(1, name);
  for (auto i : ints) a.varint(8, static_cast<uint64_t>(i));
  a.varint(20, 7);  // INTS
  return a;
}

inline Proto onnxNode(const std::string& op, const std::vector<std::string>& in,
                      const std::string& out, const std::vector<Proto>& attrs = {}) {
  Proto n;
  for (const auto& i : in) n.bytes(1, i);
  n.bytes(2, out).bytes(3, out + "_node").bytes(4, op);
  for (const auto& a : attrs) n.message(5, a);
  return n;
}

/// The graph's first two nodes: `one` [1, 1, 1, 1] = the input's first channel's mean * unit.
inline Proto unitGraph(const std::string& name, float unit) {
  Proto graph;
  graph.message(1, onnxNode("GlobalAveragePool", {"input"}, "pooled"));
  graph.message(
      1, onnxNode("Conv", {"pooled", "unit_w"}, "one", {onnxIntsAttr("kernel_shape", {1, 1})}));
  graph.bytes(2, name);
  graph.message(5, onnxTensor("unit_w", {1, 3, 1, 1}, {unit, 0.f, 0.f}));
  return graph;
}

inline std::string onnxModel(const Proto& graph) {
  Proto opset;
  opset.bytes(1, "").varint(2, 10);
  Proto model;
  model.varint(1, 6).bytes(2, "jointflow-tests").message(7, graph).message(8, opset);
  return model.str();
}

/// The model bytes; `outputs` are {name, {1, C, h, w} CV_32F tensor}, all of the same h, w.
inline std::string constantMapsOnnx(const std::vector<std::pair<std::string, cv::Mat>>& outputs) {
  Proto graph = unitGraph("constant_maps", 1.f / 255.f);
  for (const auto& [name, t] : outputs) {
    const int c = t.size[1], h = t.size[2], w = t.size[3];
    graph.message(
        1, onnxNode("ConvTranspose", {"one", name + "_w"}, name,
                    {onnxIntsAttr("kernel_shape", {h, w}), onnxIntsAttr("strides", {1, 1})}));
    const float* p = t.ptr<float>();
    graph.message(5, onnxTensor(name + "_w", {1, c, h, w}, std::vector<float>(p, p + t.total())));
  }
  graph.message(11, onnxValueInfo("input", {"1", "3", "H", "W"}));
  for (const auto& [name, t] : outputs) {
    graph.message(12, onnxValueInfo(name, {"1", std::to_string(t.size[1]),
                                           std::to_string(t.size[2]), std::to_string(t.size[3])}));
  }
  return onnxModel(graph);
}

/// A model with one output `name`, the {1, C, N} CV_32F tensor `t`, for an input scaled to
/// [0, 1] whose first channel is 1 everywhere (the YOLO pose model's input contract: RGB / 255,
/// so a frame whose red channel is 255): ConvTranspose to [1, C, 1, N], then Reshape (cv::dnn
/// 4.6's Squeeze keeps the axis).
inline std::string constantSequenceOnnx(const std::string& name, const cv::Mat& t) {
  Proto graph = unitGraph("constant_sequence", 1.f);
  const int c = t.size[1], n = t.size[2];
  graph.message(1,
                onnxNode("ConvTranspose", {"one", "sequence_w"}, "sequence",
                         {onnxIntsAttr("kernel_shape", {1, n}), onnxIntsAttr("strides", {1, 1})}));
  graph.message(1, onnxNode("Reshape", {"sequence", "sequence_shape"}, name));
  graph.message(5, onnxInt64Tensor("sequence_shape", {1, c, n}));
  const float* p = t.ptr<float>();
  graph.message(5, onnxTensor("sequence_w", {1, c, 1, n}, std::vector<float>(p, p + t.total())));
  graph.message(11, onnxValueInfo("input", {"1", "3", "H", "W"}));
  graph.message(12, onnxValueInfo(name, {"1", std::to_string(c), std::to_string(n)}));
  return onnxModel(graph);
}

}  // namespace jointflow::test
