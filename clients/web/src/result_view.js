// The result side of the page: the list of problems under the editor, the facts of an answer, the
// image element's object URL, and downloads. In: plain values and callbacks; out: DOM contents.
const $ = (id) => document.getElementById(id);

export function showProblems(items, reveal) {
  const list = $("problems");
  list.replaceChildren();
  for (const { pointer, detail, severity } of items) {
    const li = document.createElement("li");
    li.className = severity || "error";
    if (pointer !== null && pointer !== undefined) {
      const link = document.createElement("button");
      link.type = "button";
      link.className = "pointer";
      link.textContent = pointer === "" ? "(whole request)" : pointer;
      link.title = "Show this field in the editor";
      link.addEventListener("click", () => reveal(pointer));
      li.append(link, " ");
    }
    li.append(detail);  // text, never HTML: details can quote the request
    list.append(li);
  }
}

export function replaceImage(img, previous, blob) {
  if (previous) URL.revokeObjectURL(previous.url);
  const url = URL.createObjectURL(blob);
  img.src = url;
  return url;
}

export function showStats(result, warningCount) {
  const counts = result.counts || {};
  const rows = [
    ["scene id", result.sceneId],
    ["BSP cache", result.cache],
    ["polygons", counts.polygons],
    ["polygons drawn", counts.polygons_drawn],
    ["fragments", counts.fragments],
    ["placement warnings", warningCount],
  ].filter(([, v]) => v !== undefined && v !== "");  // a PNG answer carries fewer facts than JSON
  $("stats").replaceChildren(...rows.flatMap(([k, v]) => {
    const dt = document.createElement("dt");
    dt.textContent = k;
    const dd = document.createElement("dd");
    dd.textContent = String(v);
    return [dt, dd];
  }));
}

export function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
