fn main() {
    let mut app = prism::App::with(prism::DefaultPlugins);
    app.resources.source = prism::app::SceneSource::File(std::env::args().nth(1).unwrap().into());
    app.setup().unwrap();
    let s = app.resources.scene.as_ref().unwrap();
    let b = prism::accel::WideBvh::build(&s.prims);
    println!("{}", b.dump());
}
