// view.js: what both pages draw: the bundled world from one camera, lit by the
// volume alone (no lamp, no environment), so every lit pixel is the volume's light.
// A page's back end is its query string: ?webgpu, else WebGL2.
export const SIZE = { width: 480, height: 320 };
export const CAMERA = { fov: 50, near: 0.1, far: 400, position: [26, 18, 30] };
export const WEBGPU = new URLSearchParams(location.search).has('webgpu');
// The context as both pages make it: R3F's alpha, no multisampling (three's and
// R3F's antialias defaults differ), WebGL2's kept for the screenshot.
export const GL = { antialias: false, alpha: true, preserveDrawingBuffer: true };
