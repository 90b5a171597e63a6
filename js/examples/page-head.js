// The head of the pages that run three.js and the package from this repository, served from
// its root: js/examples, the three.js benchmark (js/bench/three/page.html) and web/'s three.js
// test page (web/test/three/index.html). One import map for them all (three from
// js/node_modules, the package from js/src, its wasm from js/dist) and an empty icon (no
// favicon request). A classic script in the head: the map must be in place before any module
// loads, and an import map cannot come from a file of its own.
{
  const imports = {
    three: '/js/node_modules/three/build/three.module.js',
    'three/webgpu': '/js/node_modules/three/build/three.webgpu.js',
    'three/tsl': '/js/node_modules/three/build/three.tsl.js',
    'three/addons/': '/js/node_modules/three/examples/jsm/',
    'three-subdivide': '/js/node_modules/three-subdivide/src/index.js',
    tessella: '/js/src/index.js',
    'tessella/three': '/js/src/three.js',
  };
  const map = document.createElement('script');
  map.type = 'importmap';
  map.textContent = JSON.stringify({ imports });
  const icon = document.createElement('link');
  icon.rel = 'icon';
  icon.href = 'data:,';
  document.currentScript.after(map, icon);
}
