// The parts of three.js the viewer uses, bundled by build.sh into one minified script
// that defines the global THREE (src/clearance/view/static/three.min.js).
export {
  AmbientLight, ArrowHelper, AxesHelper, Box3, BoxGeometry, BufferAttribute, BufferGeometry,
  Color, CylinderGeometry, DirectionalLight, DoubleSide, EdgesGeometry,
  Float32BufferAttribute, GridHelper, Group, HemisphereLight, Line, LineBasicMaterial,
  LineSegments, MathUtils, Matrix3, Matrix4, Mesh, MeshBasicMaterial, MeshStandardMaterial,
  Object3D, PerspectiveCamera, Quaternion, REVISION, SRGBColorSpace, Scene, Sphere,
  SphereGeometry, Vector2, Vector3, WebGLRenderer,
} from "three";
export { OrbitControls } from "three/addons/controls/OrbitControls.js";
