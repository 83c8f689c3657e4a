// vdbgi-react.js: the package's 'vdbgi/react', for React Three Fiber. <GiLight url>
// loads a volume for the Canvas's renderer and lights the meshes under it, those
// that mount later included; useGi() hands its children the runtime (occluders,
// knobs, the debug views). Plain createElement, so no JSX build step is needed to
// use the package; WebGL2 and, where the Canvas's renderer is a WebGPURenderer,
// vdbgi/webgpu, loaded only then.
import { createContext, createElement, useContext, useEffect, useLayoutEffect, useRef, useState } from 'react';
import { useThree } from '@react-three/fiber';
import { GiRuntime, loadGi } from './vdbgi.js';

const GiContext = createContext(null);

// The runtime of the nearest <GiLight> above, or null (outside one, or while its
// WebGPU runtime loads).
export function useGi() {
  return useContext(GiContext);
}

// <GiLight url="world.gi.gz" set perFragment enabled debug onLoad onError onProgress
// maxBytes timeout {...group props}>: a group whose meshes take the volume's light.
// The meshes are lit as GiRuntime.light() lights them: perFragment 'auto' (the
// default) waits for the volume, whose probe spacing decides per mesh; set and
// perFragment reach a material when it is first lit (apply() lights one once).
// A change of url loads the new volume and shows it once loaded; the runtime (and
// the volume it shows) is disposed with the component. Errors go to onError, or are
// thrown to the nearest error boundary when there is none.
export function GiLight({ url, set = 'world', perFragment = 'auto', enabled = true, debug = 'off',
  onLoad, onError, onProgress, maxBytes, timeout, children, ...props }) {
  const gl = useThree((s) => s.gl);
  const invalidate = useThree((s) => s.invalidate);
  const group = useRef(null);
  const [runtime, setRuntime] = useState(null);
  const [spacing, setSpacing] = useState(null); // the shown volume's, for perFragment 'auto'
  const [error, setError] = useState(null);
  // The callbacks of the latest render, read when a load ends (not reasons to load again).
  const calls = useRef({});
  calls.current = { onLoad, onError, onProgress };

  useEffect(() => {
    let made = null, gone = false;
    const start = gl.isWebGPURenderer
      ? import('./vdbgi-webgpu.js').then((m) => new m.GiRuntime())
      : Promise.resolve(new GiRuntime());
    start.then((r) => {
      if (gone) return r.dispose();
      made = r;
      setRuntime(r);
    }, setError);
    return () => { gone = true; made?.dispose(); };
  }, [gl]);

  useEffect(() => {
    if (!runtime) return undefined;
    const abort = new AbortController();
    loadGi(url, { renderer: gl, signal: abort.signal, maxBytes, timeout,
      onProgress: (p) => calls.current.onProgress?.(p) })
      .then((volume) => {
        if (abort.signal.aborted) return volume.dispose();
        runtime.setVolume(volume);
        setSpacing(volume.info.spacing);
        invalidate();
        calls.current.onLoad?.(volume);
      }, (e) => {
        if (abort.signal.aborted) return;
        if (calls.current.onError) calls.current.onError(e);
        else setError(e);
      });
    return () => abort.abort();
  }, [runtime, url, gl, maxBytes, timeout, invalidate]);

  useEffect(() => {
    if (!runtime) return;
    runtime.enabled = enabled;
    runtime.debug = debug;
    invalidate();
  }, [runtime, enabled, debug, invalidate]);

  // What is under the group now, then whatever joins it later (three dispatches
  // childadded on the parent alone, so every object under the group is watched).
  useLayoutEffect(() => {
    const root = group.current;
    if (!runtime || !root || (perFragment === 'auto' && spacing === null)) return undefined;
    const options = { set, perFragment };
    const watched = new Set();
    const added = (e) => { runtime.light(e.child, options); watch(e.child); invalidate(); };
    const watch = (tree) => tree.traverse((o) => {
      if (watched.has(o)) return;
      watched.add(o);
      o.addEventListener('childadded', added);
    });
    runtime.light(root, options);
    watch(root);
    invalidate();
    return () => { for (const o of watched) o.removeEventListener('childadded', added); };
  }, [runtime, set, perFragment, spacing, invalidate]);

  if (error) throw error;
  return createElement(GiContext.Provider, { value: runtime },
    createElement('group', { ref: group, ...props }, children));
}
