#include "render/gbuffer_pass.h"

#include <shared/frame.h>
#include <shared/ray_work.h>

#include <array>
#include <stdexcept>

namespace hdof {
namespace {

constexpr std::array<VkFormat, 1> kColorFormats = {VK_FORMAT_R32_SFLOAT};

gpu::RenderPass createRenderPass(const gpu::Context& context, VkSampleCountFlagBits samples) {
  std::vector<VkAttachmentDescription> attachments;
  std::vector<VkAttachmentReference> colorRefs;
  for (VkFormat format : kColorFormats) {
    VkAttachmentDescription a{};
    a.format = format;
    a.samples = samples;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = VK_IMAGE_LAYOUT_GENERAL;
    a.finalLayout = VK_IMAGE_LAYOUT_GENERAL;
    colorRefs.push_back({static_cast<uint32_t>(attachments.size()), VK_IMAGE_LAYOUT_GENERAL});
    attachments.push_back(a);
  }
  VkAttachmentDescription depth{};
  depth.format = VK_FORMAT_D32_SFLOAT;
  depth.samples = samples;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  depth.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  depth.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  VkAttachmentReference depthRef{static_cast<uint32_t>(attachments.size()),
                                 VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  attachments.push_back(depth);

  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = static_cast<uint32_t>(colorRefs.size());
  subpass.pColorAttachments = colorRefs.data();
  subpass.pDepthStencilAttachment = &depthRef;
  // Earlier compute passes read these targets; later ones read what this pass writes.
  VkSubpassDependency dependencies[2] = {};
  dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[0].dstSubpass = 0;
  dependencies[0].srcStageMask =
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependencies[0].srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
  dependencies[0].dstStageMask =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
  dependencies[0].dstAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  dependencies[1].srcSubpass = 0;
  dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dependencies[1].dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  dependencies[1].dstAccessMask = VK_ACCESS_SHADER_READ_BIT;

  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = static_cast<uint32_t>(attachments.size());
  info.pAttachments = attachments.data();
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 2;
  info.pDependencies = dependencies;
  VkRenderPass renderPass = VK_NULL_HANDLE;
  VK_CHECK(vkCreateRenderPass(context.device(), &info, nullptr, &renderPass));
  return gpu::RenderPass(context.device(), renderPass);
}

gpu::Pipeline createRasterPipeline(const gpu::Context& context, VkPipelineLayout layout,
                                   VkRenderPass renderPass, VkSampleCountFlagBits samples) {
  gpu::ShaderModule vertex = gpu::createShaderModule(context, "gbuffer.vert");
  gpu::ShaderModule fragment = gpu::createShaderModule(context, "gbuffer.frag");
  VkPipelineShaderStageCreateInfo stages[2] = {};
  stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vertex;
  stages[0].pName = "main";
  stages[1] = stages[0];
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = fragment;

  VkVertexInputBindingDescription binding{0, sizeof(glm::vec3), VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription attributes[] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  VkPipelineVertexInputStateCreateInfo vertexInput{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertexInput.vertexBindingDescriptionCount = 1;
  vertexInput.pVertexBindingDescriptions = &binding;
  vertexInput.vertexAttributeDescriptionCount = std::size(attributes);
  vertexInput.pVertexAttributeDescriptions = attributes;
  VkPipelineInputAssemblyStateCreateInfo inputAssembly{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  inputAssembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rasterization{
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rasterization.polygonMode = VK_POLYGON_MODE_FILL;
  rasterization.cullMode = VK_CULL_MODE_NONE;  // the ray tracer sees both sides too
  rasterization.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rasterization.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = samples;
  VkPipelineDepthStencilStateCreateInfo depth{
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = VK_TRUE;
  depth.depthCompareOp = VK_COMPARE_OP_LESS;
  std::array<VkPipelineColorBlendAttachmentState, kColorFormats.size()> blends{};
  for (auto& b : blends) b.colorWriteMask = 0xf;
  VkPipelineColorBlendStateCreateInfo blend{
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = static_cast<uint32_t>(blends.size());
  blend.pAttachments = blends.data();
  VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamicStates;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &vertexInput;
  info.pInputAssemblyState = &inputAssembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &rasterization;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = layout;
  info.renderPass = renderPass;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateGraphicsPipelines(context.device(), context.pipelineCache(), 1, &info, nullptr,
                                     &pipeline));
  context.setName(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(pipeline),
                  samples == VK_SAMPLE_COUNT_1_BIT ? "gbuffer" : "gbuffer multisampled");
  return gpu::Pipeline(context.device(), pipeline);
}

// A still view's first frames after the first: several samples per pixel.
bool isMultisampledFrame(const gpu::FrameUniforms& uniforms) {
  return uniforms.rasterSample > 0 && uniforms.rasterSample <= gpu::kMultisampledFrames;
}

const std::array<gpu::ShaderInterface, 2> kRasterStages = {
    gpu::reflectShader(embeddedShader("gbuffer.vert")),
    gpu::reflectShader(embeddedShader("gbuffer.frag"))};

}  // namespace

struct GBufferPass::Rasters {
  Rasters(const gpu::Context& context, const gpu::SetLayout& sceneSet)
      : layout(context, "gbuffer", kRasterStages, &sceneSet),
        singlePass(createRenderPass(context, VK_SAMPLE_COUNT_1_BIT)),
        multisampledPass(createRenderPass(context, kSamples)),
        single(createRasterPipeline(context, layout.get(), singlePass, VK_SAMPLE_COUNT_1_BIT)),
        multisampled(createRasterPipeline(context, layout.get(), multisampledPass, kSamples)) {}

  static constexpr auto kSamples = VkSampleCountFlagBits(gpu::kStillRasterSamples);
  gpu::ProgramLayout layout;
  gpu::RenderPass singlePass, multisampledPass;
  gpu::Pipeline single, multisampled;
};

GBufferPass::GBufferPass(const gpu::Context& context, const Scene& cpuScene, const GpuScene& scene)
    : context_(context),
      scene_(scene),
      runs_(buildTriangleRuns(cpuScene)),
      rasters_(context.shared<Rasters>("gbuffer|" + scene.setLayout().key(),
                                       [&] { return Rasters(context, scene.setLayout()); })),
      resolve_(context, "gbuffer_resolve.comp", &scene.setLayout()),
      resolveFirstTriangle_(context, "gbuffer_resolve.comp", &scene.setLayout(), {{"kStep", 1}}),
      resolveOtherTriangles_(context, "gbuffer_resolve.comp", &scene.setLayout(), {{"kStep", 2}}),
      sharedIndirect_(context, "ray_mask_indirect.comp"),
      antialiasStill_(context, "antialias.comp", nullptr, {{"kStillSamples", 1}}),
      antialias_(context, "antialias.comp"),
      antialiasFirst_(context, "antialias.comp", nullptr, {{"kFirstSample", 1}}) {}

void GBufferPass::bindImages(const GBufferImages& images, uint32_t width, uint32_t height) {
  extent_ = {width, height};
  auto framebuffer = [&](VkRenderPass renderPass, const gpu::Image& visibility,
                         const gpu::Image& depth) {
    VkImageView views[] = {visibility.view(), depth.view()};
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = renderPass;
    info.attachmentCount = std::size(views);
    info.pAttachments = views;
    info.width = width;
    info.height = height;
    info.layers = 1;
    VkFramebuffer handle = VK_NULL_HANDLE;
    VK_CHECK(vkCreateFramebuffer(context_.device(), &info, nullptr, &handle));
    return gpu::Framebuffer(context_.device(), handle);
  };
  singleFramebuffer_ = framebuffer(rasters_->singlePass, images.visibility, images.depth);
  multisampledFramebuffer_ = framebuffer(rasters_->multisampledPass, images.multisampledVisibility,
                                         images.multisampledDepth);
}

void GBufferPass::drawVisibility(VkCommandBuffer cmd, bool multisampled, const gpu::Bind& frame,
                                 const gpu::FrameUniforms& uniforms) const {
  VkClearValue clears[2] = {};
  clears[0].color.float32[0] = -1.0f;  // no triangle
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = multisampled ? rasters_->multisampledPass : rasters_->singlePass;
  begin.framebuffer = multisampled ? multisampledFramebuffer_ : singleFramebuffer_;
  begin.renderArea = {{0, 0}, extent_};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0.0f, 0.0f, float(extent_.width), float(extent_.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, extent_};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                    multisampled ? rasters_->multisampled : rasters_->single);
  const gpu::ProgramLayout& layout = rasters_->layout;
  if (layout.readsScene()) scene_.bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout.get());
  layout.bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, std::span(&frame, 1), {});
  VkBuffer corners = scene_.cornerBuffer().get();
  VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &corners, &offset);
  for (const TriangleRange& range : visibleTriangles(runs_, uniforms.viewProj))
    vkCmdDraw(cmd, range.triangleCount * 3, 1, range.firstTriangle * 3, 0);
  vkCmdEndRenderPass(cmd);
}

void GBufferPass::record(StepRecorder& steps, const GBufferImages& images,
                         const gpu::FrameUniforms& uniforms, bool historyValid) const {
  bool multisampled = isMultisampledFrame(uniforms);
  steps.step("visibility", [&](VkCommandBuffer cmd) {
    drawVisibility(cmd, multisampled, gpu::Bind("Frame", steps.frameUniforms()), uniforms);
  });
  std::initializer_list<gpu::Bind> resolveBindings = {
      {"visibility", images.visibility},
      {"multisampledVisibility", images.multisampledVisibility},
      {"outColor", images.rasterColor},
      {"outSpecular", images.specular},
      {"outNormalDepth", images.normalDepth},
      {"outMotion", images.motion},
      {"workList", images.sharedPixels}};
  if (!multisampled) {
    steps.dispatch(resolve_, resolveBindings, gpu::Grid::over(images.color), {}, "gbuffer");
  } else {
    steps.step("gbuffer_list_clear", [&](VkCommandBuffer cmd) {
      vkCmdFillBuffer(cmd, images.sharedPixels.get(), 0, sizeof(gpu::RayWorkHeader), 0);
    });
    steps.dispatch(resolveFirstTriangle_, resolveBindings, gpu::Grid::over(images.color), {},
                   "gbuffer");
    steps.dispatch(sharedIndirect_, {{"workList", images.sharedPixels}}, gpu::Grid::threads(1), {},
                   "gbuffer_list");
    steps.dispatch(resolveOtherTriangles_, resolveBindings,
                   gpu::Grid::indirect(images.sharedPixels), {}, "gbuffer_shared");
  }
  steps.step("antialias_history", [&](VkCommandBuffer cmd) {
    gpu::copyImage(cmd, images.color, images.colorHistory);
  });
  uint32_t valid = historyValid ? 1u : 0u;
  // Without history, the first frame's edges are smoothed spatially, unless the request asks for
  // samples at the pixel centres (pixelJitter off: no anti-aliasing at all).
  bool first = !historyValid && uniforms.pixelJitter != 0;
  steps.dispatch(uniforms.rasterSample > 0 ? antialiasStill_
                 : first                   ? antialiasFirst_
                                           : antialias_,
                 {{"rasterColor", images.rasterColor},
                  {"history", images.colorHistory},
                  {"motion", images.motion},
                  {"outColor", images.color},
                  {"normalDepth", images.normalDepth},
                  {"specular", images.specular},
                  {"samplesAveraged", images.samplesAveraged}},
                 gpu::Grid::over(images.color), valid);
}

}  // namespace hdof
