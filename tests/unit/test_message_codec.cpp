// The wire protocol's codec: every class of bad input gets its error code and field, good
// messages their values; and the frame message round-trips.
#include "net/message_codec.h"
#include "net/server_messages.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace hdof::net {
namespace {

const Limits kLimits{640, 480, 8, 4096, 2};

ParsedMessage parse(const std::string& text) { return parseClientMessage(text, kLimits); }

void expectError(const std::string& text, ErrorCode code, const std::string& field) {
  ParsedMessage parsed = parse(text);
  ASSERT_FALSE(parsed.ok()) << text;
  EXPECT_EQ(errorCodeName(parsed.error.code), std::string(errorCodeName(code)))
      << text << ": " << parsed.error.message;
  EXPECT_EQ(parsed.error.field, field) << text << ": " << parsed.error.message;
  EXPECT_FALSE(parsed.error.message.empty());
  EXPECT_EQ(parsed.error.message.find('\n'), std::string::npos);
}

const std::string kCamera =
    R"({"type":"camera","seq":3,"position":[1,2,3],"target":[0,0,0])";

TEST(MessageCodec, ValidMessagesGiveTheirValues) {
  ParsedMessage hello = parse(
      R"({"type":"hello","protocol":1,"token":"t","viewport":{"width":320,"height":200},"scene":"builtin:dof"})");
  ASSERT_TRUE(hello.ok()) << hello.error.message;
  const auto& h = std::get<HelloMessage>(*hello.message);
  EXPECT_EQ(h.viewport.width, 320u);
  EXPECT_EQ(h.viewport.height, 200u);
  EXPECT_EQ(h.token, "t");
  EXPECT_EQ(h.scene, "builtin:dof");

  ParsedMessage camera = parse(kCamera + "}");
  ASSERT_TRUE(camera.ok()) << camera.error.message;
  const auto& c = std::get<CameraMessage>(*camera.message);
  EXPECT_EQ(c.seq, 3u);
  EXPECT_EQ(c.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(c.up, glm::vec3(0, 1, 0));

  ParsedMessage lens = parse(
      R"({"type":"lens","seq":4,"focal_length_mm":35,"f_number":1.4,"focus_distance":2.5,"blades":6,"blade_rotation_deg":10})");
  ASSERT_TRUE(lens.ok()) << lens.error.message;
  EXPECT_EQ(std::get<LensMessage>(*lens.message).blades, 6u);
  EXPECT_EQ(std::get<LensMessage>(*lens.message).sensor, Sensor{}) << "full frame unless named";
  ParsedMessage aps = parse(
      R"({"type":"lens","seq":4,"focal_length_mm":35,"f_number":1.4,"focus_distance":2.5,"sensor_width_mm":23.6,"sensor_height_mm":15.6})");
  ASSERT_TRUE(aps.ok()) << aps.error.message;
  EXPECT_EQ(std::get<LensMessage>(*aps.message).sensor, (Sensor{23.6f, 15.6f}));

  ParsedMessage focus = parse(R"({"type":"focus_at","seq":5,"x":10.5,"y":20,"pull_ms":300})");
  ASSERT_TRUE(focus.ok());
  EXPECT_FLOAT_EQ(std::get<FocusAtMessage>(*focus.message).pullMs, 300.0f);

  ParsedMessage pick = parse(R"({"type":"pick","id":9,"x":3,"y":4.5})");
  ASSERT_TRUE(pick.ok()) << pick.error.message;
  EXPECT_EQ(std::get<PickMessage>(*pick.message).id, 9u);
  EXPECT_FLOAT_EQ(std::get<PickMessage>(*pick.message).y, 4.5f);

  ParsedMessage mode = parse(R"({"type":"mode","seq":6,"mode":"hybrid","view":"mask"})");
  ASSERT_TRUE(mode.ok());
  EXPECT_EQ(std::get<ModeMessage>(*mode.message).mode, RenderMode::Hybrid);
  EXPECT_EQ(std::get<ModeMessage>(*mode.message).view, DebugView::Mask);

  ParsedMessage settings = parse(R"({"type":"settings","rays_per_pixel":8,"max_fps":30})");
  ASSERT_TRUE(settings.ok());
  const auto& s = std::get<SettingsMessage>(*settings.message);
  EXPECT_EQ(s.raysPerPixel, 8u);
  EXPECT_EQ(s.maxFps, 30.0);
  EXPECT_FALSE(s.jpegQualityStill);

  ParsedMessage ack = parse(R"({"type":"ack","frame":4294967295})");
  ASSERT_TRUE(ack.ok());
  EXPECT_EQ(std::get<AckMessage>(*ack.message).frame, 4294967295u);
  // JSON Schema's integers include 2.0.
  EXPECT_TRUE(parse(R"({"type":"ack","frame":2.0})").ok());
}

TEST(MessageCodec, NotJsonOrNotAnObjectIsBadJson) {
  for (const char* text : {"", "not json", "{", "[1,2]", "42", "\"hello\"", "null",
                           "{\"type\":\"ack\",\"frame\":1} trailing", "{\"a\":NaN}",
                           "{\"a\":Infinity}", "{\"type\":\"ack\",\"frame\":1e999}"})
    expectError(text, ErrorCode::BadJson, "");
  expectError("{\"type\":\"hello\xff\"}", ErrorCode::BadJson, "");  // not UTF-8
}

TEST(MessageCodec, TypeMustBeAKnownString) {
  expectError(R"({})", ErrorCode::BadField, "type");
  expectError(R"({"type":7})", ErrorCode::BadField, "type");
  expectError(R"({"type":"warp"})", ErrorCode::UnknownType, "type");
  expectError(R"({"type":"Hello"})", ErrorCode::UnknownType, "type");
}

TEST(MessageCodec, WrongFieldTypesAreBadFields) {
  expectError(R"({"type":"camera","seq":"3","position":[1,2,3],"target":[0,0,0]})",
              ErrorCode::BadField, "seq");
  expectError(R"({"type":"camera","seq":3,"position":[1,2],"target":[0,0,0]})",
              ErrorCode::BadField, "position");
  expectError(R"({"type":"camera","seq":3,"position":[1,2,"x"],"target":[0,0,0]})",
              ErrorCode::BadField, "position");
  expectError(R"({"type":"ack","frame":1.5})", ErrorCode::BadField, "frame");
  expectError(R"({"type":"hello","protocol":1,"viewport":[640,480]})", ErrorCode::BadField,
              "viewport");
  expectError(R"({"type":"hello","protocol":1,"viewport":{"width":"640","height":480}})",
              ErrorCode::BadField, "viewport.width");
  expectError(R"({"type":"hello","protocol":1,"token":5,"viewport":{"width":64,"height":48}})",
              ErrorCode::BadField, "token");
  expectError(R"({"type":"mode","seq":1,"mode":3})", ErrorCode::BadField, "mode");
}

TEST(MessageCodec, MissingAndUnknownFieldsAreBadFields) {
  expectError(R"({"type":"camera","seq":3,"target":[0,0,0]})", ErrorCode::BadField,
              "position");
  expectError(kCamera + R"(,"zoom":2})", ErrorCode::BadField, "zoom");
  // The field of view follows the lens: a camera that still sends one is told where it went.
  ParsedMessage fov = parse(kCamera + R"(,"fov_y_deg":40})");
  ASSERT_FALSE(fov.ok());
  EXPECT_EQ(fov.error.field, "fov_y_deg");
  EXPECT_NE(fov.error.message.find("focal_length_mm"), std::string::npos) << fov.error.message;
  expectError(R"({"type":"hello","protocol":1})", ErrorCode::BadField, "viewport");
  expectError(R"({"type":"hello","protocol":1,"viewport":{"width":64,"height":48,"depth":3}})",
              ErrorCode::BadField, "viewport.depth");
  expectError(R"({"type":"ack"})", ErrorCode::BadField, "frame");
  expectError(R"({"type":"pick","x":1,"y":1})", ErrorCode::BadField, "id");
  expectError(R"({"type":"pick","id":1,"x":1,"y":1,"seq":2})", ErrorCode::BadField, "seq");
}

TEST(MessageCodec, ValuesOutOfRange) {
  expectError(R"({"type":"camera","seq":-1,"position":[1,2,3],"target":[0,0,0]})",
              ErrorCode::OutOfRange, "seq");
  expectError(
      R"({"type":"camera","seq":4294967296,"position":[1,2,3],"target":[0,0,0]})",
      ErrorCode::OutOfRange, "seq");
  expectError(R"({"type":"camera","seq":1,"position":[1,2,3],"target":[1,2,3]})",
              ErrorCode::OutOfRange, "target");
  expectError(
      R"({"type":"camera","seq":1,"position":[0,0,0],"target":[0,1,0],"up":[0,2,0]})",
      ErrorCode::OutOfRange, "up");
  expectError(R"({"type":"camera","seq":1,"position":[0,0,1e30],"target":[0,0,0]})",
              ErrorCode::OutOfRange, "position");
  expectError(R"({"type":"hello","protocol":2,"viewport":{"width":64,"height":48}})",
              ErrorCode::OutOfRange, "protocol");
  expectError(R"({"type":"hello","protocol":1,"viewport":{"width":8,"height":48}})",
              ErrorCode::OutOfRange, "viewport.width");
  expectError(R"({"type":"hello","protocol":1,"viewport":{"width":64,"height":481}})",
              ErrorCode::OutOfRange, "viewport.height");
  expectError(R"({"type":"hello","protocol":1,"token":")" + std::string(300, 'x') +
                  R"(","viewport":{"width":64,"height":48}})",
              ErrorCode::OutOfRange, "token");
  const std::string lens = R"({"type":"lens","seq":1,"focal_length_mm":50,)";
  expectError(lens + R"("f_number":0.1,"focus_distance":2})", ErrorCode::OutOfRange, "f_number");
  expectError(lens + R"("f_number":2,"focus_distance":0})", ErrorCode::OutOfRange,
              "focus_distance");
  expectError(lens + R"("f_number":2,"focus_distance":2,"blades":2})", ErrorCode::OutOfRange,
              "blades");
  expectError(lens + R"("f_number":2,"focus_distance":2,"sensor_width_mm":0.5,"sensor_height_mm":24})",
              ErrorCode::OutOfRange, "sensor_width_mm");
  expectError(lens + R"("f_number":2,"focus_distance":2,"sensor_width_mm":36,"sensor_height_mm":1e9})",
              ErrorCode::OutOfRange, "sensor_height_mm");
  expectError(lens + R"("f_number":2,"focus_distance":2,"sensor_width_mm":36})", ErrorCode::BadField,
              "sensor_height_mm");
  expectError(lens + R"("f_number":2,"focus_distance":2,"sensor_height_mm":"24"})",
              ErrorCode::BadField, "sensor_height_mm");
  expectError(lens + R"("f_number":2,"focus_distance":2,"blades":17})", ErrorCode::OutOfRange,
              "blades");
  expectError(R"({"type":"focus_at","seq":1,"x":-1,"y":0})", ErrorCode::OutOfRange, "x");
  expectError(R"({"type":"focus_at","seq":1,"x":1,"y":0,"pull_ms":20000})", ErrorCode::OutOfRange,
              "pull_ms");
  expectError(R"({"type":"pick","id":-1,"x":1,"y":0})", ErrorCode::OutOfRange, "id");
  expectError(R"({"type":"pick","id":1,"x":1,"y":-2})", ErrorCode::OutOfRange, "y");
  expectError(R"({"type":"mode","seq":1,"mode":"reference"})", ErrorCode::OutOfRange, "mode");
  expectError(R"({"type":"mode","seq":1,"mode":"hybrid","view":"sideways"})", ErrorCode::OutOfRange,
              "view");
  expectError(R"({"type":"mode","seq":1,"mode":"pinhole","view":"mask"})", ErrorCode::BadField,
              "view");
  expectError(R"({"type":"settings","rays_per_pixel":9})", ErrorCode::OutOfRange, "rays_per_pixel");
  expectError(R"({"type":"settings","jpeg_quality_still":0})", ErrorCode::OutOfRange,
              "jpeg_quality_still");
  expectError(R"({"type":"settings","resolution_scale":2})", ErrorCode::OutOfRange,
              "resolution_scale");
  expectError(R"({"type":"ack","frame":0})", ErrorCode::OutOfRange, "frame");
}

TEST(MessageCodec, OversizeAndDeepInputNeverCrash) {
  expectError(R"({"type":"settings","pad":")" + std::string(5000, 'x') + "\"}",
              ErrorCode::OutOfRange, "");
  Limits big = kLimits;
  big.maxMessageBytes = 1 << 20;
  std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_FALSE(parseClientMessage(deep, big).ok());
  EXPECT_FALSE(parseClientMessage(std::string("\0\0\0", 3), big).ok());
}

TEST(ServerMessages, FrameMessageRoundTrips) {
  std::vector<uint8_t> jpeg = {0xff, 0xd8, 1, 2, 3, 0xff, 0xd9};
  std::vector<uint8_t> message = frameMessage({7, 640, 360, 42}, R"({"frame":7})", jpeg, 16);
  ASSERT_EQ(message.size(), 16 + kFrameHeaderBytes + 11 + jpeg.size());
  std::span<const uint8_t> body(message.data() + 16, message.size() - 16);
  EXPECT_EQ(std::string(body.begin(), body.begin() + 4), "HDOF");
  auto parsed = parseFrameMessage(body);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->header.frame, 7u);
  EXPECT_EQ(parsed->header.width, 640u);
  EXPECT_EQ(parsed->header.height, 360u);
  EXPECT_EQ(parsed->header.seq, 42u);
  EXPECT_EQ(parsed->stats, R"({"frame":7})");
  EXPECT_EQ(std::vector<uint8_t>(parsed->jpeg.begin(), parsed->jpeg.end()), jpeg);
  EXPECT_FALSE(parseFrameMessage(body.subspan(0, 20)));
  std::vector<uint8_t> wrongLength(body.begin(), body.end());
  wrongLength[24] = 0xff;
  EXPECT_FALSE(parseFrameMessage(wrongLength));
}

TEST(ServerMessages, WelcomeAndErrorFollowTheSchemas) {
  Welcome welcome;
  welcome.session = "3";
  welcome.sceneName = "builtin:dof";
  welcome.bounds.grow(glm::vec3(-1.0f));
  welcome.bounds.grow(glm::vec3(1.0f));
  welcome.cameras.push_back(SceneCamera{"main"});
  SceneCamera suggested{"suggested"};
  suggested.focusDistance = 2.5f;
  welcome.cameras.push_back(suggested);
  welcome.viewport = {640, 360};
  nlohmann::json w = nlohmann::json::parse(welcomeMessage(welcome));
  // 50 mm on full frame at 16:9: 36 x 20.25 mm, 2 atan(18 / 50) by 2 atan(10.125 / 50).
  EXPECT_NEAR(w["fov_x_deg"].get<double>(), 39.598, 1e-3);
  EXPECT_NEAR(w["fov_y_deg"].get<double>(), 22.895, 1e-3);
  EXPECT_NEAR(w["scene"]["cameras"][0]["fov_y_deg"].get<double>(), glm::degrees(0.7), 1e-4)
      << "the scene camera's own, for the client to frame it on its sensor";
  EXPECT_EQ(w["type"], "welcome");
  EXPECT_EQ(w["limits"]["max_unacked_frames"], 2);
  EXPECT_EQ(w["scene"]["cameras"][0]["name"], "main");
  EXPECT_FALSE(w["scene"]["cameras"][0].contains("focus_distance")) << "none known";
  EXPECT_EQ(w["scene"]["cameras"][1]["focus_distance"], 2.5);
  // A scene camera less its name, focus and field of view (the lens's) is a valid camera message.
  nlohmann::json sceneCamera = w["scene"]["cameras"][1];
  sceneCamera.erase("name");
  sceneCamera.erase("focus_distance");
  sceneCamera.erase("fov_y_deg");
  sceneCamera["type"] = "camera";
  sceneCamera["seq"] = 1;
  EXPECT_TRUE(parse(sceneCamera.dump()).ok()) << sceneCamera.dump();
  EXPECT_EQ(w["camera"]["type"], "camera");
  EXPECT_EQ(w["views"], nlohmann::json(debugViewList()));
  EXPECT_EQ(w["views"][0], "final");
  // Every welcome field is in the schema, and every field it requires is in the welcome.
  std::ifstream schemaFile(HDOF_SOURCE_DIR "/protocol/schemas/welcome.json");
  ASSERT_TRUE(schemaFile) << "protocol/schemas/welcome.json";
  const nlohmann::json schema = nlohmann::json::parse(schemaFile);
  for (const auto& [field, value] : w.items())
    EXPECT_TRUE(schema["properties"].contains(field)) << field << " is not in welcome.json";
  for (const auto& field : schema["required"])
    EXPECT_TRUE(w.contains(field.get<std::string>())) << field << " is missing from the welcome";
  // The welcome's camera and lens are valid client messages.
  EXPECT_TRUE(parse(w["camera"].dump()).ok()) << w["camera"].dump();
  EXPECT_TRUE(parse(w["lens"].dump()).ok()) << w["lens"].dump();

  nlohmann::json e = nlohmann::json::parse(errorMessage({ErrorCode::OutOfRange, "too big", "x"}));
  EXPECT_EQ(
      e,
      nlohmann::json(
          {{"type", "error"}, {"code", "out_of_range"}, {"message", "too big"}, {"field", "x"}}));
  EXPECT_FALSE(
      nlohmann::json::parse(errorMessage({ErrorCode::BadJson, "bad", ""})).contains("field"));
}

TEST(ServerMessages, PickedAndFrameStatsFollowTheSchemas) {
  auto schemaOf = [](const char* name) {
    std::ifstream file(std::string(HDOF_SOURCE_DIR "/protocol/schemas/") + name);
    EXPECT_TRUE(file) << name;
    return nlohmann::json::parse(file, nullptr, false);
  };
  nlohmann::json picked = schemaOf("picked.json");
  nlohmann::json hit = nlohmann::json::parse(pickedMessage(4, SurfaceHit{{1, 2, 3}, 2.5f, 3.0f}));
  EXPECT_EQ(hit, nlohmann::json({{"type", "picked"}, {"id", 4}, {"hit", true},
                                 {"point", {1.0, 2.0, 3.0}}, {"depth", 2.5}, {"distance", 3.0}}));
  for (const auto& [field, value] : hit.items())
    EXPECT_TRUE(picked["properties"].contains(field)) << field << " is not in picked.json";
  EXPECT_EQ(nlohmann::json::parse(pickedMessage(5, std::nullopt)),
            nlohmann::json({{"type", "picked"}, {"id", 5}, {"hit", false}}));

  nlohmann::json statsSchema = schemaOf("frame-stats.json");
  FrameStatsMessage stats;
  stats.inputToSendMs = 1.0;
  nlohmann::json fields = nlohmann::json::parse(frameStatsJson(stats));
  for (const auto& [field, value] : fields.items())
    EXPECT_TRUE(statsSchema["properties"].contains(field)) << field << " is not in frame-stats.json";
  EXPECT_TRUE(fields.contains("accumulation_target") && fields.contains("moving"));
}

}  // namespace
}  // namespace hdof::net
