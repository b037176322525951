// Run in the report page when it has loaded: counts the images that loaded and names the broken ones
// on <body> (data-images-total, -loaded, -broken), which report_test reads through headless Chromium.
window.addEventListener("load", function () {
  var images = Array.prototype.slice.call(document.images);
  var broken = images.filter(function (image) { return !(image.complete && image.naturalWidth > 0); });
  document.body.dataset.imagesTotal = String(images.length);
  document.body.dataset.imagesLoaded = String(images.length - broken.length);
  document.body.dataset.imagesBroken = broken.map(function (image) { return image.getAttribute("src"); }).join(" ");
});
