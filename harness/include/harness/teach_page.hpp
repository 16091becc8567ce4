// teach_page.hpp: the HTML page of one `refraster teach` run.
//
// Implements: teach_page_html, which turns the run's document (a textbook algorithm's image,
// GL's rules' image, the pixels where they differ and why, the input geometry, and the
// algorithm's state at every step) into one self-contained HTML file: the three images side by
// side (algorithm, GL, difference mask) zoomable on canvases, the pixel under the pointer, the
// list of differences, a step-through of the algorithm (buttons, keys, `#step=K`, and
// `#press=...` for tests that cannot click), the notes and the command that reproduces the page.
//
// Deliberately does not: render anything, read or write files, or check the document beyond
// what drawing it needs (a missing field draws as empty). Nothing on the page refers to the
// network or to another file: the data, the styles and the scripts are inline.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace harness {

// The teaching page of one `refraster teach` run: one self-contained HTML file (no network,
// no external file: scripts, styles and images inline) drawn from `data`:
//   algorithm, title, scene, scene_file, gl_source, summary: strings;
//   width, height: the target (pixel (x, y), row 0 at the bottom);
//   algorithm_rgba, gl_rgba: width * height * 4 bytes each, row 0 the bottom row;
//   differences: [{x, y, algorithm (weight 0..1), gl (bool: GL lit it), reason}];
//   input: [{x0, y0, x1, y1, role}] in window coordinates (pixel units, y up);
//   steps: [{title, state: [[name, value]], pixels: [[x, y, weight]], overlay: [segments]}]
//     (weight 0: the pixel was considered and rejected);
//   notes: [string].
// The data is embedded as JSON in <script type="application/json" id="teach-data">, every
// '<', '>' and '&' written as a \u escape, so that no string in it can end the element.
std::string teach_page_html(const nlohmann::json& data);

}  // namespace harness
