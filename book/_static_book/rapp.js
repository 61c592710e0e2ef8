// rapp: a figure shown smaller than it was drawn (a multi-panel row on a phone) opens full size
// on click, in a new tab. Figures already shown at their own size do nothing.
document.addEventListener("click", (event) => {
  const img = event.target.closest(".cell_output img");
  if (!img || img.closest("a, .animation, .jupyter-widgets")) return;
  if (img.naturalWidth > 1.15 * img.clientWidth) window.open(img.src, "_blank", "noopener");
});
