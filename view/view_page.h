#pragma once
// The live view's page (view/page/index.html, embedded at build time): one self-contained HTML
// file that connects back to the server it came from over the Foxglove WebSocket protocol and
// draws what it is sent.
namespace navd::view {

const char* ViewPage();

}  // namespace navd::view
