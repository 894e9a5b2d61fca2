// The capture console's one page (GET /): plain HTML, CSS and script, no build step and nothing
// fetched from elsewhere, so it works offline. It reads /api/state, listens to /api/events and
// posts the buttons to /api/...; docs/console.md describes the API.
#pragma once

#include <string>

namespace mesocap::app {

std::string ConsolePage(const std::string& session_name);

}  // namespace mesocap::app
