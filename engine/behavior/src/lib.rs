//! Behavior trees and strategy files in RON: language, validation, interpretation and hot reload.
