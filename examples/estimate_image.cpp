// estimate_image: the core library alone, image in, poses out as one JSON object on stdout:
//   {"poses": [{"score": s, "box": [x, y, w, h], "keypoints": [[x, y, score], ... 17, COCO
//   order]}]}
// in frame pixels. Errors go to stderr with a non-zero exit status.
//
//   estimate_image IMAGE [--model movenet|posenet] [--input-size native|WxH|max:N]
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Estimates the 2D poses of all people in an image (JointFlow core)"};
  std::string image_path, model = "movenet", input_size, model_path;
  app.add_option("image", image_path, "image file")->required();
  app.add_option("--model", model, "spatial model")->check(CLI::IsMember({"movenet", "posenet"}));
  app.add_option("--input-size", input_size,
                 "native, WxH (letterboxed) or max:N (default: the model's default, max:640)");
  app.add_option("--model-file", model_path, "ONNX file instead of the shipped one");
  CLI11_PARSE(app, argc, argv);

  try {
    jointflow::SpatialOptions options;
    if (!input_size.empty()) options.input_size = jointflow::InputSize::parse(input_size);
    options.model_path = model_path;
    const cv::Mat image = cv::imread(image_path, cv::IMREAD_COLOR);
    if (image.empty()) throw jointflow::Error("cannot read an image from " + image_path);
    auto estimator =
        jointflow::createSpatialModel(jointflow::parseEnum<jointflow::ModelType>(model), options);
    const jointflow::SpatialResult result = estimator->estimate(image);

    nlohmann::json poses = nlohmann::json::array();
    for (const auto& p : result.poses) {
      nlohmann::json keypoints = nlohmann::json::array();
      for (const auto& k : p.keypoints) keypoints.push_back({k.x, k.y, k.score});
      poses.push_back({{"score", p.score},
                       {"box", {p.box.x, p.box.y, p.box.w, p.box.h}},
                       {"keypoints", keypoints}});
    }
    std::cout << nlohmann::json{{"poses", poses}}.dump() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "estimate_image: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
